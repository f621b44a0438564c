//! Shells on lavapipe: the same voxels (a MagicaVoxel sample and a patch of the built-in
//! terrain, at levels 0 and 1) rendered with opaque greedy quads and with vertical shell runs
//! (`gpu_backend::render::passes::shells`) must agree: at most 1 % of pixels off by more than
//! 8/255 in any channel. The shells' per-face ambient occlusion is what makes them agree (a
//! render without it misses the bar), and the shell pass draws every uploaded run.

#[allow(dead_code, reason = "each test file uses part of the shared helpers")]
mod image_support;

use gpu_backend::DeviceOptions;
use gpu_backend::GpuContext;
use gpu_backend::render::far::FarRequest;
use gpu_backend::render::{OpaquePath, RenderError, Renderer, RendererConfig};
use gpu_backend::residency::ResidencyError;
use gpu_backend::test_support::headless_or_skip;
use image_support::scenes::TestScene;
use image_support::{Image, write_pngs};
use mesher::BlockClasses;
use mesher::lod::{Geometry, NodeMesh, NodeSettings, downsample_levels, mesh_nodes};
use render_model::cull::LodSettings;
use render_model::lighting::Lighting;
use render_model::resident::ChunkMeshData;
use tests::sample_data;
use viewer::gpu_view::upload_nodes;
use viewer::scene::vox::load_vox_file;
use voxel_core::formats::{ChunkLayersData, ShellRun};
use voxel_core::storage::{PaletteChunk, WorldMap};
use voxel_core::{ChunkCoord, ChunkSize, FormatError, MaterialPalette};

const WIDTH: u32 = 192;
const HEIGHT: u32 = 144;
/// A channel counts as off when it differs by more than this (of 255).
const COLOUR: u8 = 8;
/// The share of pixels that may be off.
const SHARE: f64 = 0.01;
/// The tighter channel difference of the AO check: on these views the meshers' AO changes
/// the lit colour of about 3 to 6 % of the pixels by more than 2/255 (and fewer than 1 % by
/// more than 8/255), so at 2/255 shells without AO miss the 1 % bar and shells with it keep
/// it (measured on lavapipe: at most 0.1 % with AO, at least 3.3 % without).
const AO_COLOUR: u8 = 2;

/// Meshes every chunk of `world` (of `level`) with `geometry`; `ao` keeps the hiding mask the
/// shells' AO reads (the node's far blocks).
fn nodes(
    world: &WorldMap<PaletteChunk>,
    level: u32,
    scene: &TestScene,
    geometry: Geometry,
    ao: bool,
) -> Vec<NodeMesh> {
    let classes = BlockClasses::from_palette(&scene.palette);
    let mut coords: Vec<ChunkCoord> = world.iter().map(|(c, _)| c).collect();
    coords.sort_unstable();
    let settings = NodeSettings {
        far_blocks: ao,
        geometry,
        ..Default::default()
    };
    mesh_nodes(world, level, &coords, &classes, &settings).expect("nodes")
}

/// Renders `nodes` (all of one level, every one selected: a budget of 0 pixels keeps level 0,
/// one of 10^6 pixels never refines level 1) and returns the image, with the shell pass's
/// `(nodes, runs)` drawn.
fn render(ctx: &GpuContext, scene: &TestScene, nodes: &[NodeMesh]) -> (Image, (u32, u32)) {
    render_on(ctx, scene, nodes, OpaquePath::Raster)
}

/// [`render`] with the opaque quads drawn the `opaque` way.
fn render_on(
    ctx: &GpuContext,
    scene: &TestScene,
    nodes: &[NodeMesh],
    opaque: OpaquePath,
) -> (Image, (u32, u32)) {
    let config = RendererConfig {
        opaque,
        ..RendererConfig::new(WIDTH, HEIGHT, scene.world.size())
            .with_far(FarRequest::Off, 1 << 22)
            .with_shells(1 << 22)
    };
    let mut renderer = Renderer::new(ctx, &config, &scene.palette).expect("renderer");
    upload_nodes(&mut renderer, nodes).expect("upload");
    renderer.set_camera(&scene.camera);
    let level = nodes.first().map_or(0, |n| n.level);
    renderer
        .set_lod(Some(LodSettings {
            budget_px: if level == 0 { 0.0 } else { 1e6 },
            far_cell_px: 0.0,
            hysteresis: 0.0,
        }))
        .expect("settings");
    renderer
        .set_lighting(&Lighting::default())
        .expect("the default lighting renders");
    // Two frames: the second's occlusion culling starts from the first's visibility.
    renderer.render().expect("frame");
    renderer.render().expect("frame");
    let stats = renderer
        .shell_stats()
        .expect("stats")
        .expect("a shell pass");
    let frame = renderer.read_image().expect("readback");
    let image = Image {
        width: WIDTH,
        height: HEIGHT,
        rgba: frame.rgba,
        depth: frame.depth,
        surfaces: None,
    };
    (image, stats)
}

/// The share of pixels with a channel off by more than `colour`.
fn share_off_by(a: &Image, b: &Image, colour: u8) -> f64 {
    let off = a
        .rgba
        .chunks_exact(4)
        .zip(b.rgba.chunks_exact(4))
        .filter(|(p, q)| (0..3).any(|k| p[k].abs_diff(q[k]) > colour))
        .count();
    off as f64 / (a.width * a.height) as f64
}

/// The share of pixels with a channel off by more than [`COLOUR`].
fn share_off(a: &Image, b: &Image) -> f64 {
    share_off_by(a, b, COLOUR)
}

/// How much of the image shows geometry (not the sky): the share of pixels with a reversed-Z
/// depth above 0.
fn covered(image: &Image) -> f64 {
    image.depth.iter().filter(|&&d| d > 0.0).count() as f64 / image.depth.len() as f64
}

/// Greedy against shells at levels 0 and 1 of `scene`; with `IMAGE_TESTS_WRITE` set writes
/// the PNGs. Returns the shares off by more than [`AO_COLOUR`] of (shells with AO, shells
/// without AO) per level.
fn compare_scene(ctx: &GpuContext, name: &str, scene: &TestScene) -> Vec<(f64, f64)> {
    let classes = BlockClasses::from_palette(&scene.palette);
    let coarse = downsample_levels(&scene.world, &classes, 1).expect("downsampling");
    let mut out = Vec::new();
    for (level, world) in [(0, &scene.world), (1, &coarse[0])] {
        let greedy_nodes = nodes(world, level, scene, Geometry::Greedy, true);
        let shell_nodes = nodes(world, level, scene, Geometry::Shells, true);
        let bare_nodes = nodes(world, level, scene, Geometry::Shells, false);
        let (greedy, none) = render(ctx, scene, &greedy_nodes);
        assert_eq!(none, (0, 0), "greedy nodes have no runs");
        let (shells, drawn) = render(ctx, scene, &shell_nodes);
        let (bare, _) = render(ctx, scene, &bare_nodes);
        let runs: usize = shell_nodes.iter().map(|n| n.shells.len()).sum();
        let quads: usize = greedy_nodes
            .iter()
            .map(|n| n.mesh.blocky.opaque.len())
            .sum();
        let with_nodes = shell_nodes.iter().filter(|n| !n.shells.is_empty()).count();
        let label = format!("{name}-level{level}");
        let (off, off_bare) = (share_off(&shells, &greedy), share_off(&bare, &greedy));
        eprintln!(
            "{label}: {runs} runs ({} B) vs {quads} quads ({} B); shell pass drew {drawn:?}; \
             covered {:.3}; off by > {COLOUR}: with AO {:.4}, without {:.4}",
            runs * 8,
            quads * 8,
            covered(&greedy),
            off,
            off_bare
        );
        if std::env::var_os("IMAGE_TESTS_WRITE").is_some() || off > SHARE {
            eprintln!("PNGs in {}", write_pngs(&label, &shells, &greedy).display());
            write_pngs(&format!("{label}-no-ao"), &bare, &greedy);
        }
        assert!(
            covered(&greedy) > 0.05,
            "{label}: the view shows too little"
        );
        assert_eq!(
            drawn,
            (with_nodes as u32, runs as u32),
            "{label}: every run drawn"
        );
        assert!(
            off <= SHARE,
            "{label}: {off:.4} of pixels off (bar {SHARE})"
        );
        let (fine, fine_bare) = (
            share_off_by(&shells, &greedy, AO_COLOUR),
            share_off_by(&bare, &greedy, AO_COLOUR),
        );
        eprintln!("{label}: off by > {AO_COLOUR}: with AO {fine:.4}, without {fine_bare:.4}");
        out.push((fine, fine_bare));
    }
    out
}

/// At the tighter [`AO_COLOUR`] bar, shells with AO match the quads and shells without miss:
/// this fails if the shells' AO were missing.
fn assert_ao_matters(shares: &[(f64, f64)]) {
    for &(with, bare) in shares {
        assert!(
            with <= SHARE,
            "with AO {with:.4} off by > {AO_COLOUR}: {shares:?}"
        );
        assert!(
            bare > SHARE,
            "without AO only {bare:.4} off by > {AO_COLOUR}: {shares:?}"
        );
    }
}

fn vox_scene() -> Option<TestScene> {
    let path = sample_data("vox")?.join("chr_knight.vox");
    let scene = load_vox_file(&path, ChunkSize::S16, 1 << 24).expect("the sample loads");
    let (lo, hi) = scene.bounds.expect("voxels");
    Some(TestScene {
        world: scene.world,
        palette: scene.palette,
        camera: viewer::scene::camera_looking_at(lo, hi),
    })
}

#[test]
fn shells_match_greedy_quads_of_the_built_in_terrain() {
    let Some(ctx) = headless_or_skip(&DeviceOptions::default()) else {
        return;
    };
    let shares = compare_scene(&ctx, "shells-terrain", &image_support::scenes::terrain());
    assert_ao_matters(&shares);
}

#[test]
fn shells_match_greedy_quads_of_a_magicavoxel_model() {
    let Some(ctx) = headless_or_skip(&DeviceOptions::default()) else {
        return;
    };
    let Some(scene) = vox_scene() else {
        return;
    };
    assert_ao_matters(&compare_scene(&ctx, "shells-knight", &scene));
}

#[test]
fn shells_match_greedy_quads_on_the_compute_opaque_path() {
    let Some(ctx) = headless_or_skip(&DeviceOptions::default()) else {
        return;
    };
    if !ctx.capabilities.int64_atomics {
        gpu_backend::test_support::skip("the compute opaque path needs 64-bit atomics");
        return;
    }
    // The greedy frame on the compute path, the shells (a raster overlay) on it too.
    let scene = image_support::scenes::terrain();
    let greedy_nodes = nodes(&scene.world, 0, &scene, Geometry::Greedy, true);
    let shell_nodes = nodes(&scene.world, 0, &scene, Geometry::Shells, true);
    let (greedy, _) = render_on(&ctx, &scene, &greedy_nodes, OpaquePath::Compute);
    let (shells, drawn) = render_on(&ctx, &scene, &shell_nodes, OpaquePath::Compute);
    let off = share_off(&shells, &greedy);
    eprintln!("compute path: shell pass drew {drawn:?}, {off:.4} off by > {COLOUR}");
    if off > SHARE {
        eprintln!(
            "PNGs in {}",
            write_pngs("shells-compute", &shells, &greedy).display()
        );
    }
    assert!(drawn.1 > 0 && covered(&shells) > 0.05);
    assert!(off <= SHARE, "{off:.4} of pixels off (bar {SHARE})");
}

/// An upload of `runs` (one node at the origin, level 0) to a renderer with a shell pass.
fn upload_runs(ctx: &GpuContext, runs: &[ShellRun]) -> Result<(), RenderError> {
    let config = RendererConfig::new(WIDTH, HEIGHT, ChunkSize::S16).with_shells(1 << 16);
    let mut renderer = Renderer::new(ctx, &config, &MaterialPalette::new()).expect("renderer");
    let layers = ChunkLayersData {
        shell_runs: runs,
        ..Default::default()
    };
    renderer
        .upload_chunk(&ChunkMeshData {
            coord: ChunkCoord::new(0, 0, 0),
            lod: 0,
            layers,
        })
        .map(|_| ())
}

#[test]
fn bad_shell_runs_are_refused_by_name() {
    let Some(ctx) = headless_or_skip(&DeviceOptions::default()) else {
        return;
    };
    let good = ShellRun::new(1, 2, 3, 4, 1, ShellRun::ALL_SIDES);
    assert!(upload_runs(&ctx, &[good]).is_ok());
    // (run, the field its error names): height 0, past 64 voxels, no side, wider than 64
    // voxels, and four runs that fit the format but not a 16^3 chunk.
    let cases = [
        (ShellRun::new(0, 0, 0, 0, 1, 1), "ShellRun.height"),
        (ShellRun::new(0, 0, 60, 5, 1, 1), "ShellRun.height"),
        (ShellRun::new(0, 0, 0, 1, 1, 0), "ShellRun.sides"),
        (
            ShellRun::new(60, 0, 0, 1, 1, 1).with_width(5),
            "ShellRun.width",
        ),
        (ShellRun::new(16, 0, 0, 1, 1, 1), "ShellRun.x"),
        (
            ShellRun::new(12, 0, 0, 1, 1, 1).with_width(5),
            "ShellRun.x + width",
        ),
        (ShellRun::new(0, 40, 0, 1, 1, 1), "ShellRun.z"),
        (ShellRun::new(0, 0, 10, 7, 1, 1), "ShellRun.y + height"),
    ];
    for (bad, field) in cases {
        let error = upload_runs(&ctx, &[good, bad]).expect_err("a bad run is refused");
        let RenderError::Residency(ResidencyError::BadShellRun { run: 1, error: e }) = &error
        else {
            panic!("{bad:?}: {error}");
        };
        let named = match e {
            FormatError::IntegerOutOfRange { field, .. }
            | FormatError::ReservedBitsSet { field, .. } => *field,
            other => panic!("{bad:?}: {other}"),
        };
        assert_eq!(named, field, "{bad:?}: {error}");
    }
    // Without a shell pass (no shell space) runs are refused too, naming the kind.
    let config = RendererConfig::new(WIDTH, HEIGHT, ChunkSize::S16);
    let mut renderer = Renderer::new(&ctx, &config, &MaterialPalette::new()).expect("renderer");
    let runs = [good];
    let error = renderer
        .upload_chunk(&ChunkMeshData {
            coord: ChunkCoord::new(0, 0, 0),
            lod: 0,
            layers: ChunkLayersData {
                shell_runs: &runs,
                ..Default::default()
            },
        })
        .expect_err("no shell space");
    assert!(error.to_string().contains("shell runs"), "{error}");
}

/// The shadow pass's visibility words of `nodes` (level 0) drawn with sun shadows and sky
/// visibility on.
fn shadow_words(
    ctx: &GpuContext,
    scene: &TestScene,
    nodes: &[NodeMesh],
) -> Vec<render_model::lighting::shadow::Visibility> {
    let config = RendererConfig::new(WIDTH, HEIGHT, scene.world.size())
        .with_far(FarRequest::Off, 1 << 22)
        .with_shells(1 << 22);
    let mut renderer = Renderer::new(ctx, &config, &scene.palette).expect("renderer");
    upload_nodes(&mut renderer, nodes).expect("upload");
    renderer.set_camera(&scene.camera);
    renderer
        .set_lighting(&Lighting {
            shadows: render_model::lighting::shadow::ShadowSettings::default(),
            ..Lighting::default()
        })
        .expect("the lighting renders");
    renderer.render().expect("frame");
    renderer
        .read_shadow_visibility()
        .expect("readback")
        .expect("shadows are on")
}

/// Runs cast shadows and block the sky as the quads of the same voxels do: the shadow grid
/// is filled from the runs (`shadow_fill_shells`), so the visibility words of the shell frame
/// are the greedy frame's but at the few pixels where the two surfaces' depths differ.
#[test]
fn shells_cast_shadows_like_greedy_quads() {
    let Some(ctx) = headless_or_skip(&DeviceOptions::default()) else {
        return;
    };
    // A floor with a pillar 8 blocks tall: one run per pillar column.
    let mut palette = MaterialPalette::new();
    let floor = palette
        .push(voxel_core::Material::opaque(120, 160, 90))
        .unwrap();
    let stone = palette
        .push(voxel_core::Material::opaque(170, 170, 180))
        .unwrap();
    let mut scene = image_support::scenes::scene_from_fn(
        palette,
        ChunkSize::S16,
        [-12, -1, -12],
        [12, 8, 12],
        0,
        move |x, y, z| {
            if y == -1 {
                floor
            } else if (0..2).contains(&x) && (0..2).contains(&z) && y < 8 {
                stone
            } else {
                voxel_core::BlockId::AIR
            }
        },
    );
    scene.camera = render_model::camera::Camera {
        voxel: voxel_core::WorldPos::new(-2, 20, 10),
        fraction: glam::DVec3::new(0.3, 0.4, 0.6),
        yaw: 0.0,
        pitch: -1.0,
        fov_y: 1.0,
        near: render_model::camera::Camera::DEFAULT_NEAR,
    };
    let world = &scene.world;
    let greedy = shadow_words(
        &ctx,
        &scene,
        &nodes(world, 0, &scene, Geometry::Greedy, true),
    );
    let shells = shadow_words(
        &ctx,
        &scene,
        &nodes(world, 0, &scene, Geometry::Shells, true),
    );
    // The pillar's shadow on the floor and its faces away from the sun.
    let shadowed = greedy.iter().filter(|v| !v.sun).count();
    assert!(shadowed > 300, "only {shadowed} pixels without sun");
    // A run that cast nothing would leave its shadow's floor pixels sunlit: hundreds of
    // pixels; the surfaces' own edges differ on a few.
    let differ = greedy.iter().zip(&shells).filter(|(a, b)| a != b).count();
    assert!(
        differ * 10 <= shadowed,
        "{differ} pixels' visibility differs, against {shadowed} shadowed"
    );
}

/// A node the far path draws is not drawn by its runs too: with far draws on and a far
/// threshold every node passes, the shell pass draws no run and the frame is the far path's,
/// as it is with greedy quads; with far draws off every run is drawn.
#[test]
fn far_drawn_nodes_draw_no_runs() {
    let Some(ctx) = headless_or_skip(&DeviceOptions::default()) else {
        return;
    };
    let scene = image_support::scenes::terrain();
    let frame = |geometry, far: FarRequest| {
        let config = RendererConfig::new(WIDTH, HEIGHT, scene.world.size())
            .with_far(far, 1 << 22)
            .with_shells(1 << 22);
        let mut renderer = Renderer::new(&ctx, &config, &scene.palette).expect("renderer");
        let nodes = nodes(&scene.world, 0, &scene, geometry, true);
        upload_nodes(&mut renderer, &nodes).expect("upload");
        renderer.set_camera(&scene.camera);
        renderer
            .set_lod(Some(LodSettings {
                budget_px: 0.0,
                far_cell_px: 1e9,
                hysteresis: 0.0,
            }))
            .expect("settings");
        renderer.render().expect("frame");
        renderer.render().expect("frame");
        let (_, runs) = renderer
            .shell_stats()
            .expect("stats")
            .expect("a shell pass");
        (renderer.read_image().expect("readback").rgba, runs)
    };
    let splat = FarRequest::Path(gpu_backend::render::far::FarPath::Splat);
    let (greedy, _) = frame(Geometry::Greedy, splat);
    let (shells, runs) = frame(Geometry::Shells, splat);
    assert_eq!(runs, 0, "far-drawn nodes drew runs");
    assert!(greedy == shells, "the far-drawn frames differ");
    let (_, all) = frame(Geometry::Shells, FarRequest::Off);
    assert!(all > 1000, "without far draws {all} runs drawn");
}
