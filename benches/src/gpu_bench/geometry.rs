//! `gpu_bench --geometry greedy,shells,heightmap`: the same terrain with its opaque surface
//! extracted as greedy quads, as vertical shells (SBgl's runs) or as heightmap cubes (SBgl's
//! heightmap path: one box per column top, no far-draw data), each on its own renderer at one
//! setting:
//! resident bytes in all and per node, the opaque instances, the CPU time to mesh, the GPU
//! time of the frame and of the passes that draw the opaque surface, and the image
//! difference from the greedy frame.
//!
//! The geometries run twice, the second time in reverse order, and each GPU figure is the
//! mean of the two medians. A geometry whose nodes carry no far-draw data (heightmap) runs
//! without a far path.

use serde::{Deserialize, Serialize};

use gpu_backend::GpuContext;
use gpu_backend::render::Renderer;
use mesher::lod::Geometry;

use super::{BenchError, image_error, measure};
use crate::gpu_scene::LodTerrain;

/// One geometry's figures.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct GeometryRow {
    /// `greedy`, `shells` or `heightmap`.
    pub geometry: String,
    /// Nodes resident.
    pub nodes: u64,
    /// Opaque instances: greedy quads (skirts included), or runs (heightmap boxes) plus the
    /// skirt quads.
    pub opaque_instances: u64,
    /// Opaque greedy quads resident (skirts and transparent quads included).
    pub quads: u64,
    /// Shell runs resident.
    pub runs: u64,
    /// Node data resident, bytes, every kind.
    pub resident_bytes: u64,
    /// Node data resident per kind, bytes.
    pub resident_by_kind: Vec<(String, u64)>,
    /// Seconds to mesh the nodes (all threads).
    pub mesh_seconds: f64,
    /// GPU time of the frame, microseconds (sum of the pass timestamps).
    pub gpu_total_us: f64,
    /// GPU time of the passes that draw opaque surfaces, microseconds, by label.
    pub surface_passes: Vec<(String, f64)>,
    /// Mean absolute difference from the greedy frame, 8-bit steps.
    pub mean_abs: f64,
    /// Share of pixels (0..=1) off by more than 8/255 from the greedy frame.
    pub share_over_8: f64,
}

/// The table and what it was measured on.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct GeometryReport {
    /// The adapter, as wgpu names it.
    pub adapter: String,
    /// The setting, in words.
    pub setting: String,
    /// Timed frames per geometry and round.
    pub frames: usize,
    /// The rows, in the order asked.
    pub rows: Vec<GeometryRow>,
}

/// Pass labels that draw opaque surfaces.
const SURFACE_PASSES: [&str; 5] = [
    "quad raster",
    "quad raster late",
    "gbuffer",
    "gbuffer late",
    "shells",
];

/// The geometry named `name` (`greedy`, `shells`, `heightmap`); anything else is refused by
/// name.
pub fn parse_geometry(name: &str) -> Result<Geometry, String> {
    match name {
        "greedy" => Ok(Geometry::Greedy),
        "shells" => Ok(Geometry::Shells),
        "heightmap" => Ok(Geometry::Heightmap),
        other => Err(format!(
            "{other:?} is not a geometry (greedy, shells, heightmap)"
        )),
    }
}

/// The name of `geometry` in the table.
pub fn geometry_name(geometry: Geometry) -> &'static str {
    match geometry {
        Geometry::Greedy => "greedy",
        Geometry::Shells => "shells",
        Geometry::Heightmap => "heightmap",
    }
}

/// One geometry to measure: its terrain, and its renderer with the terrain resident and the
/// view set up.
#[derive(Debug)]
pub struct GeometryRun<'a> {
    /// The geometry.
    pub geometry: Geometry,
    /// The terrain meshed with it.
    pub terrain: &'a LodTerrain,
    /// Its renderer.
    pub renderer: Renderer,
    /// Its last timed frame, RGBA8 (empty until [`bench_geometry`] has run).
    pub image: Vec<u8>,
}

/// Measures every run, `frames` timed frames per run and round; the image differences are
/// against the first run's frame (greedy, when asked first).
pub fn bench_geometry(
    ctx: &GpuContext,
    runs: &mut [GeometryRun<'_>],
    frames: usize,
    setting: String,
) -> Result<GeometryReport, BenchError> {
    if runs.is_empty() {
        return Err(BenchError::BadConfig("no geometry to measure".to_owned()));
    }
    let n = runs.len();
    let mut totals = vec![Vec::new(); n];
    let mut passes = vec![Vec::new(); n];
    let mut images = vec![Vec::new(); n];
    for round in 0..2 {
        let order: Vec<usize> = if round == 0 {
            (0..n).collect()
        } else {
            (0..n).rev().collect()
        };
        for i in order {
            let (medians, _, _, image) = measure(ctx, &mut runs[i].renderer, frames)?;
            totals[i].push(medians.iter().map(|p| p.micros).sum::<f64>());
            passes[i].extend(medians);
            images[i] = image.rgba;
        }
    }
    for (run, image) in runs.iter_mut().zip(&images) {
        run.image.clone_from(image);
    }
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len().max(1) as f64;
    let mut rows = Vec::new();
    for (i, run) in runs.iter().enumerate() {
        let error = image_error(&images[i], &images[0]).unwrap_or_default();
        let resident_by_kind: Vec<(String, u64)> = run
            .renderer
            .resident_bytes()
            .into_iter()
            .map(|(k, v)| (k.to_owned(), v))
            .collect();
        let surface_passes = SURFACE_PASSES
            .iter()
            .filter_map(|&label| {
                let times: Vec<f64> = passes[i]
                    .iter()
                    .filter(|p: &&super::PassMedian| p.label == label)
                    .map(|p| p.micros)
                    .collect();
                (!times.is_empty()).then(|| (label.to_owned(), mean(&times)))
            })
            .collect();
        let quads = run.terrain.quad_count();
        let runs_count = run.terrain.shell_count();
        rows.push(GeometryRow {
            geometry: geometry_name(run.geometry).to_owned(),
            nodes: run.renderer.chunk_count() as u64,
            opaque_instances: quads + runs_count,
            quads,
            runs: runs_count,
            resident_bytes: node_bytes(&resident_by_kind),
            resident_by_kind,
            mesh_seconds: run.terrain.mesh_seconds,
            gpu_total_us: mean(&totals[i]),
            surface_passes,
            mean_abs: error.mean_abs,
            share_over_8: error.share_over_8,
        });
    }
    Ok(GeometryReport {
        adapter: ctx.capabilities.adapter.to_string(),
        setting,
        frames,
        rows,
    })
}

/// The node data of a renderer's resident bytes: the gigabuffer kinds (the rows named
/// `DataKind::name`), not the tables and frame buffers every geometry has alike.
fn node_bytes(by_kind: &[(String, u64)]) -> u64 {
    by_kind
        .iter()
        .filter(|(k, _)| {
            voxel_core::formats::DataKind::ALL
                .iter()
                .any(|kind| kind.name() == k)
        })
        .map(|(_, v)| v)
        .sum()
}

/// The table as Markdown.
pub fn geometry_markdown(report: &GeometryReport) -> String {
    let mut s = format!(
        "{}; {}; {} timed frames per geometry, twice (forward, then reverse order), means of \
         the medians.\n\n",
        report.adapter, report.setting, report.frames
    );
    s.push_str(
        "| geometry | nodes | opaque instances (quads + runs) | node bytes | bytes per node | mesh s | GPU frame µs | surface passes µs | MAE vs greedy | pixels off > 8/255 |\n",
    );
    s.push_str("| --- | ---: | ---: | ---: | ---: | ---: | ---: | --- | ---: | ---: |\n");
    for row in &report.rows {
        let passes = row
            .surface_passes
            .iter()
            .map(|(label, us)| format!("{label} {us:.1}"))
            .collect::<Vec<_>>()
            .join(", ");
        s.push_str(&format!(
            "| {} | {} | {} + {} | {} | {:.0} | {:.2} | {:.1} | {} | {:.3} | {:.3} % |\n",
            row.geometry,
            row.nodes,
            row.quads,
            row.runs,
            row.resident_bytes,
            row.resident_bytes as f64 / row.nodes.max(1) as f64,
            row.mesh_seconds,
            row.gpu_total_us,
            if passes.is_empty() {
                "-".to_owned()
            } else {
                passes
            },
            row.mean_abs,
            row.share_over_8 * 100.0
        ));
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn geometries_parse_and_others_are_refused_by_name() {
        assert_eq!(parse_geometry("greedy"), Ok(Geometry::Greedy));
        assert_eq!(parse_geometry("shells"), Ok(Geometry::Shells));
        assert_eq!(parse_geometry("heightmap"), Ok(Geometry::Heightmap));
        assert!(parse_geometry("cubes").unwrap_err().contains("\"cubes\""));
        for g in [Geometry::Greedy, Geometry::Shells, Geometry::Heightmap] {
            assert_eq!(parse_geometry(geometry_name(g)), Ok(g));
        }
    }

    #[test]
    fn node_bytes_count_the_gigabuffer_kinds_only() {
        let by_kind = vec![
            ("quads".to_owned(), 800),
            (voxel_core::formats::DataKind::Shells.name().to_owned(), 80),
            ("chunk table".to_owned(), 5000),
            ("shell draws".to_owned(), 700),
        ];
        assert_eq!(node_bytes(&by_kind), 880);
    }
}
