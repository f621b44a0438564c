//! The GPU benchmark: the viewer's terrain at every level of detail, drawn by the deferred
//! renderer for each error budget, far path and full-screen path asked for, with GPU time per
//! pass, what was drawn, resident bytes, CPU frame time and the image error against full
//! detail (see `benches::gpu_bench`). Prints Markdown tables; `--out FILE` also writes them,
//! `--json FILE` writes every figure.
//!
//! ```sh
//! cargo run --release -p benches --bin gpu_bench -- --side 4096 --budget 1 --far splat
//! ```

use std::process::ExitCode;
use std::time::Instant;

use benches::gpu_bench::{
    BenchConfig, BenchReport, SceneSummary, bench_camera, budget_params, grass_params, markdown,
    may_draw_grass, run, selected_by_any,
};
use benches::gpu_scene::{Clutter, LodTerrain};
use clap::{Parser, ValueEnum};
use gpu_backend::render::FullscreenPath;
use gpu_backend::render::OpaquePath;
use gpu_backend::render::far::{FarPath, FarRequest};
use gpu_backend::{DeviceOptions, GpuContext};
use voxel_core::ChunkSize;

/// A far path on the command line.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum Far {
    /// Every node meshed.
    Off,
    /// Compute splat (needs 64-bit atomics).
    Splat,
    /// Raycast sprites (one bounding quad per block, ray-box per fragment).
    Sprite,
    /// The 3 camera-facing faces of each block as quads.
    Quads3,
    /// The best the device runs.
    Auto,
}

/// A full-screen path on the command line.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum Screen {
    /// Compute passes.
    Compute,
    /// Fragment passes.
    Fragment,
}

/// An opaque quad path on the command line.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum Opaque {
    /// The G-buffer raster pass.
    Raster,
    /// The compute rasteriser into the visibility buffer.
    Compute,
}

/// Whether to render full detail.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum Reference {
    /// When the terrain is at most 4096 columns wide (full detail must fit).
    Auto,
    /// Always.
    On,
    /// Never (no image errors).
    Off,
}

/// Command-line options.
#[derive(Parser, Debug)]
#[command(about = "GPU benchmark: LOD terrain drawn by the deferred renderer, per error budget")]
struct Args {
    /// Block columns per side of the terrain square (up to 16384).
    #[arg(long, default_value_t = 4096)]
    side: u32,
    /// Chunk edge (8 or 16 for far draws; 32 and 62 mesh only).
    #[arg(long, default_value_t = 8)]
    chunk: u32,
    /// Highest level of detail built.
    #[arg(long, default_value_t = 6)]
    top_level: u32,
    /// Error budgets, pixels (repeatable or comma-separated).
    #[arg(long, value_delimiter = ',', default_value = "1")]
    budget: Vec<f32>,
    /// Render full detail too (the image errors' reference).
    #[arg(long, value_enum, default_value_t = Reference::Auto)]
    reference: Reference,
    /// Far paths (repeatable or comma-separated).
    #[arg(long, value_enum, value_delimiter = ',', default_value = "auto")]
    far: Vec<Far>,
    /// Far thresholds: nodes whose cells span at most this many pixels are far-drawn.
    #[arg(long, value_delimiter = ',', default_value = "4")]
    far_px: Vec<f32>,
    /// Full-screen paths (repeatable or comma-separated).
    #[arg(long, value_enum, value_delimiter = ',', default_value = "compute")]
    fullscreen: Vec<Screen>,
    /// Two-phase occlusion culling (repeatable or comma-separated: on, off).
    #[arg(long, value_delimiter = ',', default_value = "on", value_parser = parse_on_off)]
    occlusion: Vec<bool>,
    /// Opaque quad paths (repeatable or comma-separated).
    #[arg(long, value_enum, value_delimiter = ',', default_value = "raster")]
    opaque: Vec<Opaque>,
    /// Output width, pixels.
    #[arg(long, default_value_t = 1920)]
    width: u32,
    /// Output height, pixels.
    #[arg(long, default_value_t = 1080)]
    height: u32,
    /// Timed frames per setting.
    #[arg(long, default_value_t = 20)]
    frames: usize,
    /// Clutter units per grass top face on the level-0 chunks, drawn by the grass pass (0: no
    /// clutter, no grass pass; the viewer grows 2).
    #[arg(long, default_value_t = 0.0)]
    clutter: f32,
    /// Sun shadows and sky visibility on (`ShadowSettings::default()`; the shadow pass's
    /// steps are timed as `shadow grid` and `shadow trace`).
    #[arg(long)]
    shadows: bool,
    /// Terrain seed.
    #[arg(long, default_value_t = 1)]
    seed: i32,
    /// Also write the tables (and the setup lines) to this file.
    #[arg(long)]
    out: Option<std::path::PathBuf>,
    /// Write every figure as JSON to this file.
    #[arg(long)]
    json: Option<std::path::PathBuf>,
    /// Write the last setting's image to this PNG (with `--geometry`: each geometry's, as
    /// `STEM-<geometry>.png`).
    #[arg(long)]
    png: Option<std::path::PathBuf>,
    /// Instead of the terrain: N instances of the sample prop (`--prop-file`) on a grid, the
    /// prop cull and draw GPU times, instances drawn and the CPU time per frame, at N and at
    /// N / 100.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=10_000_000))]
    props: Option<u32>,
    /// The glTF file `--props` places.
    #[arg(long, default_value = "../shared/data/gltf/Duck.glb")]
    prop_file: std::path::PathBuf,
    /// Write the full-detail image to this PNG.
    #[arg(long)]
    reference_png: Option<std::path::PathBuf>,
    /// Instead of the settings table: the image features (FXAA, sun shadows and sky
    /// visibility, distance haze, grass) none, each alone and all, at the first budget, far
    /// path, far threshold, occlusion, opaque and full-screen setting given: each row's GPU
    /// cost and its image difference from the row without any (`benches::gpu_bench::features`).
    /// Grass needs clutter: `--clutter` defaults to the viewer's 2 with it.
    #[arg(long)]
    features: bool,
    /// Instead of the settings table: the terrain meshed with each of these geometries
    /// (comma-separated: greedy, shells, heightmap) on a renderer each, at the
    /// first setting given: node bytes, opaque instances, meshing time, GPU time and the image
    /// difference from the first geometry's frame (`benches::gpu_bench::geometry`).
    #[arg(long, value_delimiter = ',', value_parser = benches::gpu_bench::geometry::parse_geometry)]
    geometry: Vec<mesher::lod::Geometry>,
}

/// The first value of each setting list, for the single-setting tables (`--features`,
/// `--geometry`), or the flag that has none.
struct FirstSetting {
    far: FarRequest,
    occlusion: bool,
    opaque: OpaquePath,
    fullscreen: FullscreenPath,
    budget: f32,
    far_px: f32,
}

impl FirstSetting {
    fn of(args: &Args) -> Result<FirstSetting, String> {
        let first = |what: &str| format!("at least one {what} is needed");
        Ok(FirstSetting {
            far: far_request(*args.far.first().ok_or_else(|| first("--far"))?),
            occlusion: *args.occlusion.first().ok_or_else(|| first("--occlusion"))?,
            opaque: match args.opaque.first().ok_or_else(|| first("--opaque"))? {
                Opaque::Raster => OpaquePath::Raster,
                Opaque::Compute => OpaquePath::Compute,
            },
            fullscreen: match args
                .fullscreen
                .first()
                .ok_or_else(|| first("--fullscreen"))?
            {
                Screen::Compute => FullscreenPath::Compute,
                Screen::Fragment => FullscreenPath::Fragment,
            },
            budget: *args.budget.first().ok_or_else(|| first("--budget"))?,
            far_px: *args.far_px.first().ok_or_else(|| first("--far-px"))?,
        })
    }

    /// A renderer of `terrain` at this setting, the nodes `params` select resident, the bench
    /// camera set.
    fn renderer(
        &self,
        args: &Args,
        ctx: &GpuContext,
        terrain: &LodTerrain,
        params: &[render_model::cull::LodParams],
    ) -> Result<gpu_backend::render::Renderer, Box<dyn std::error::Error>> {
        let mut renderer = benches::gpu_bench::renderer_with(
            ctx,
            terrain,
            (args.width, args.height),
            self.far,
            self.occlusion,
            self.opaque,
        )?;
        renderer.set_camera(&bench_camera());
        benches::gpu_bench::upload_terrain_where(&mut renderer, terrain, |n| {
            selected_by_any(params, n.level, n.coord)
        })?;
        renderer.set_fullscreen_path(self.fullscreen);
        renderer.set_lod(Some(render_model::cull::LodSettings {
            budget_px: self.budget,
            far_cell_px: self.far_px,
            ..Default::default()
        }))?;
        Ok(renderer)
    }

    /// The setting in words, with the far path `renderer` resolved.
    fn describe(
        &self,
        args: &Args,
        terrain: &LodTerrain,
        renderer: &gpu_backend::render::Renderer,
    ) -> String {
        format!(
            "{}² columns in {}³ chunks, budget {} px, far {:?} at {} px, occlusion {}, \
             opaque {:?}, full-screen {:?}, {} x {}",
            terrain.side,
            terrain.size.edge(),
            self.budget,
            renderer.far_choice().path,
            self.far_px,
            if self.occlusion { "on" } else { "off" },
            self.opaque,
            self.fullscreen,
            args.width,
            args.height
        )
    }
}

/// Writes `lines` and `table` to `--out`, and `json` to `--json`, when given.
fn write_outputs(
    args: &Args,
    mut lines: Vec<String>,
    table: &str,
    json: String,
) -> Result<(), Box<dyn std::error::Error>> {
    println!("{table}");
    lines.push(String::new());
    lines.push(table.to_owned());
    if let Some(path) = &args.out {
        std::fs::write(path, lines.join("\n"))?;
    }
    if let Some(path) = &args.json {
        std::fs::write(path, json)?;
    }
    Ok(())
}

/// `--geometry`: the terrain meshed with each geometry (the first is `terrain`'s own, meshed
/// as greedy quads or as asked), the table written like the others.
fn bench_geometry_at(
    args: &Args,
    ctx: &GpuContext,
    make: &dyn Fn(mesher::lod::Geometry) -> Result<LodTerrain, mesher::MeshError>,
    params: &[render_model::cull::LodParams],
    lines: Vec<String>,
) -> Result<(), Box<dyn std::error::Error>> {
    use benches::gpu_bench::geometry::{GeometryRun, bench_geometry, geometry_markdown};
    let setting = FirstSetting::of(args)?;
    let terrains = args
        .geometry
        .iter()
        .map(|&g| make(g).map(|t| (g, t)))
        .collect::<Result<Vec<_>, _>>()?;
    let mut runs = Vec::new();
    for (geometry, terrain) in &terrains {
        runs.push(GeometryRun {
            geometry: *geometry,
            terrain,
            renderer: setting.renderer(args, ctx, terrain, params)?,
            image: Vec::new(),
        });
    }
    let words = setting.describe(args, &terrains[0].1, &runs[0].renderer);
    let report = bench_geometry(ctx, &mut runs, args.frames, words)?;
    // `--png a.png`: each geometry's frame as `a-<geometry>.png`.
    if let Some(path) = &args.png {
        for run in &runs {
            let name = benches::gpu_bench::geometry::geometry_name(run.geometry);
            let stem = path.file_stem().unwrap_or_default().to_string_lossy();
            let file = path.with_file_name(format!("{stem}-{name}.png"));
            let png = gpu_backend::png::encode_png(args.width, args.height, &run.image)?;
            std::fs::write(&file, png).map_err(|e| format!("{}: {e}", file.display()))?;
        }
    }
    let table = geometry_markdown(&report);
    write_outputs(args, lines, &table, serde_json::to_string_pretty(&report)?)
}

/// The renderer's far request for a command-line far path.
fn far_request(far: Far) -> FarRequest {
    match far {
        Far::Off => FarRequest::Off,
        Far::Splat => FarRequest::Path(FarPath::Splat),
        Far::Sprite => FarRequest::Path(FarPath::Sprite),
        Far::Quads3 => FarRequest::Path(FarPath::CameraQuads),
        Far::Auto => FarRequest::Auto,
    }
}

/// `--features`: the feature table on one renderer of `terrain`, written like the others.
fn bench_features_at(
    args: &Args,
    ctx: &GpuContext,
    terrain: &LodTerrain,
    params: &[render_model::cull::LodParams],
    lines: Vec<String>,
) -> Result<(), Box<dyn std::error::Error>> {
    use benches::gpu_bench::features::{bench_features, features_markdown};
    let setting = FirstSetting::of(args)?;
    let mut renderer = setting.renderer(args, ctx, terrain, params)?;
    let words = setting.describe(args, terrain, &renderer);
    let haze = terrain.side as f32 / 2.0;
    let report = bench_features(ctx, &mut renderer, args.frames, haze, words)?;
    let table = features_markdown(&report);
    write_outputs(args, lines, &table, serde_json::to_string_pretty(&report)?)
}

/// `on` or `off`.
fn parse_on_off(text: &str) -> Result<bool, String> {
    match text {
        "on" => Ok(true),
        "off" => Ok(false),
        _ => Err(format!("{text:?} is neither on nor off")),
    }
}

/// `--props N`: the prop figures at N / 100 (at least 1) and at N.
fn bench_props_at(args: &Args, n: u32) -> Result<(), Box<dyn std::error::Error>> {
    let ctx = GpuContext::new_headless(&DeviceOptions::default())?;
    eprintln!("adapter: {}", ctx.capabilities.adapter);
    println!(
        "props ({}, {}x{}, {} frames): instances | drawn | prop cull GPU ms | props GPU ms | CPU ms/frame",
        args.prop_file.display(),
        args.width,
        args.height,
        args.frames
    );
    for count in [(n / 100).max(1), n] {
        let f = benches::gpu_bench::props::bench_props(
            &ctx,
            &args.prop_file,
            count,
            (args.width, args.height),
            args.frames,
        )?;
        println!(
            "props {} | {} | {:.3} | {:.3} | {:.3}",
            f.instances, f.drawn, f.cull_ms, f.draw_ms, f.cpu_ms
        );
    }
    Ok(())
}

fn main() -> ExitCode {
    match bench(&Args::parse()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("gpu_bench: {e}");
            ExitCode::FAILURE
        }
    }
}

fn bench(args: &Args) -> Result<(), Box<dyn std::error::Error>> {
    if let Some(n) = args.props {
        return bench_props_at(args, n);
    }
    let size = ChunkSize::from_edge(args.chunk)?;
    if args.side == 0 || args.side > 16384 {
        return Err(format!("--side {} must be 1..=16384", args.side).into());
    }
    if let Some(b) = args.budget.iter().find(|b| !b.is_finite() || **b < 0.0) {
        return Err(format!("--budget {b} must be finite and at least 0").into());
    }
    let reference = match args.reference {
        Reference::Auto => args.side <= 4096,
        Reference::On => true,
        Reference::Off => false,
    };
    let ctx = GpuContext::new_headless(&DeviceOptions::default())?;
    eprintln!("adapter: {}", ctx.capabilities.adapter);
    let camera = bench_camera();
    // What the views can select: every node some budget selects from the bench camera (and all
    // of level 0 for the full-detail reference).
    let params = budget_params(&camera, &args.budget, args.top_level, args.height, size);
    let keep = |level: u32, coord: voxel_core::ChunkCoord| {
        (reference && level == 0) || selected_by_any(&params, level, coord)
    };
    let started = Instant::now();
    // The feature table's grass row needs clutter: the viewer's density unless given.
    let density = if args.features && args.clutter == 0.0 {
        2.0
    } else {
        args.clutter
    };
    let clutter_params = if density > 0.0 {
        Some(
            mesher::ClutterParams::new(density, args.seed as u64)
                .map_err(|e| format!("--clutter: {e}"))?,
        )
    } else if density == 0.0 {
        None
    } else {
        return Err(format!("--clutter {} must be at least 0", args.clutter).into());
    };
    // Clutter only where a frame can draw grass (the viewer's rule; the full-detail
    // reference's fade budget included).
    let grass = grass_params(&params, reference);
    let grass_on = |c: voxel_core::ChunkCoord| may_draw_grass(&grass, c);
    let clutter = clutter_params.map(|params| Clutter {
        params,
        on: &grass_on,
    });
    if !args.geometry.is_empty() {
        let make = |geometry| {
            LodTerrain::generate_as(
                args.side,
                size,
                args.seed,
                args.top_level,
                clutter,
                geometry,
                keep,
            )
        };
        let lines = vec![format!("adapter: {}", ctx.capabilities.adapter)];
        return bench_geometry_at(args, &ctx, &make, &params, lines);
    }
    let terrain = LodTerrain::generate_with_clutter(
        args.side,
        size,
        args.seed,
        args.top_level,
        clutter,
        keep,
    )?;
    let resident: Vec<usize> = terrain.levels.iter().map(Vec::len).collect();
    let grass_nodes = match clutter {
        Some(_) => terrain
            .levels
            .first()
            .map_or(0, |l| l.iter().filter(|n| grass_on(n.coord)).count()),
        None => 0,
    };
    let mut scene = SceneSummary {
        adapter: ctx.capabilities.adapter.to_string(),
        side: terrain.side,
        chunk_edge: size.edge(),
        width: args.width,
        height: args.height,
        chunks_per_level: terrain.chunks_per_level.clone(),
        resident_per_level: resident,
        resident_quads: terrain.quad_count(),
        resident_draw_block_words: terrain.draw_block_words(),
        resident_far_blocks: terrain.far_block_count(),
        generate_seconds: terrain.generate_seconds,
        downsample_seconds: terrain.downsample_seconds,
        mesh_seconds: terrain.mesh_seconds,
        frames: args.frames,
        ..Default::default()
    };
    let mut lines = vec![
        format!("adapter: {}", ctx.capabilities.adapter),
        format!(
            "terrain: {}² columns, {}³ chunks, levels 0..={}: {:?} chunks, {:?} resident; {} quads, \
             {} draw-block words ({} far blocks, the rest hiding masks), {} clutter units (on the {} of {} level-0 nodes within the grass reach); generated {:.2} s, downsampled {:.2} s, meshed {:.2} s ({} \
             threads), {:.1} s in all",
            terrain.side,
            size.edge(),
            args.top_level,
            scene.chunks_per_level,
            scene.resident_per_level,
            scene.resident_quads,
            scene.resident_draw_block_words,
            scene.resident_far_blocks,
            terrain.clutter_count(),
            grass_nodes,
            terrain.levels.first().map_or(0, Vec::len),
            terrain.generate_seconds,
            terrain.downsample_seconds,
            terrain.mesh_seconds,
            rayon::current_num_threads(),
            started.elapsed().as_secs_f64()
        ),
    ];
    for line in &lines {
        eprintln!("{line}");
    }
    if args.features {
        return bench_features_at(args, &ctx, &terrain, &params, lines);
    }
    let config = BenchConfig {
        width: args.width,
        height: args.height,
        frames: args.frames,
        budgets: args.budget.clone(),
        reference,
        far: args.far.iter().map(|&f| far_request(f)).collect(),
        far_cell_px: args.far_px.clone(),
        fullscreen: args
            .fullscreen
            .iter()
            .map(|s| match s {
                Screen::Compute => FullscreenPath::Compute,
                Screen::Fragment => FullscreenPath::Fragment,
            })
            .collect(),
        occlusion: args.occlusion.clone(),
        opaque: args
            .opaque
            .iter()
            .map(|o| match o {
                Opaque::Raster => OpaquePath::Raster,
                Opaque::Compute => OpaquePath::Compute,
            })
            .collect(),
        lighting: render_model::lighting::Lighting {
            shadows: if args.shadows {
                render_model::lighting::shadow::ShadowSettings::default()
            } else {
                render_model::lighting::shadow::ShadowSettings::OFF
            },
            ..Default::default()
        },
    };
    let (runs, images, choices) = run(&ctx, &terrain, &config, &mut scene)?;
    for choice in &choices {
        lines.push(format!("far draws: {choice}"));
    }
    lines.push(format!(
        "frames: {} x {}, {} timed per setting (medians); upload {:.0} ms; resident bytes: {}",
        args.width,
        args.height,
        args.frames,
        scene.upload_ms,
        scene
            .resident_bytes
            .iter()
            .map(|(k, v)| format!("{k} {v}"))
            .collect::<Vec<_>>()
            .join(", ")
    ));
    let report = BenchReport { scene, runs };
    let table = markdown(&report);
    println!("{table}");
    lines.push(String::new());
    lines.push(table);
    if let Some(path) = &args.out {
        std::fs::write(path, lines.join("\n"))?;
    }
    if let Some(path) = &args.json {
        std::fs::write(path, serde_json::to_string_pretty(&report)?)?;
    }
    let write_png = |path: &std::path::Path, image: &gpu_backend::render::FrameImage| {
        std::fs::write(
            path,
            gpu_backend::png::encode_png(image.width, image.height, &image.rgba)?,
        )?;
        eprintln!("image: {}", path.display());
        Ok::<(), Box<dyn std::error::Error>>(())
    };
    if let (Some(path), Some(image)) = (&args.png, &images.last) {
        write_png(path, image)?;
    }
    if let (Some(path), Some(image)) = (&args.reference_png, &images.reference) {
        write_png(path, image)?;
    }
    Ok(())
}
