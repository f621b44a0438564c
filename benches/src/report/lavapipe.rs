//! The budget sweep measured in this run on the machine's own Vulkan adapter (lavapipe, the
//! CPU driver, on the machines without a GPU): a small LOD terrain drawn by `gpu_bench`'s
//! runner at full detail and at every budget, read back through the same parser as the GPU
//! machine's file so the two tables share one shape. Its figures are marked with the adapter.

use gpu_backend::render::far::FarRequest;
use gpu_backend::render::{FullscreenPath, OpaquePath};
use gpu_backend::{DeviceOptions, GpuContext};
use voxel_core::ChunkSize;

use super::ReportError;
use super::image::{BudgetSweep, parse};
use crate::gpu_bench::{BenchConfig, BenchReport, SceneSummary, run};
use crate::gpu_scene::LodTerrain;

/// The budgets of the report, pixels.
pub const BUDGETS: [f32; 6] = [0.25, 0.5, 1.0, 2.0, 4.0, 8.0];

/// Coarsest LOD level of the small terrain.
const TOP_LEVEL: u32 = 3;

/// Measures the sweep over a `side x side`-column terrain in `(width, height)` frames, `frames`
/// timed per setting. `Ok(None)` when the machine has no Vulkan adapter.
pub fn measure(
    side: u32,
    (width, height): (u32, u32),
    frames: usize,
) -> Result<Option<BudgetSweep>, ReportError> {
    let ctx = match GpuContext::new_headless(&DeviceOptions::default()) {
        Ok(ctx) => ctx,
        Err(e) if e.is_no_adapter() => return Ok(None),
        Err(e) => return Err(ReportError(format!("GPU device: {e}"))),
    };
    let size = ChunkSize::S8;
    let terrain = LodTerrain::generate(side, size, 1, TOP_LEVEL, |_, _| true)
        .map_err(|e| ReportError(format!("LOD terrain: {e}")))?;
    let config = BenchConfig {
        width,
        height,
        frames: frames.max(1),
        budgets: BUDGETS.to_vec(),
        reference: true,
        far: vec![FarRequest::Auto],
        far_cell_px: vec![2.0],
        fullscreen: vec![FullscreenPath::Compute],
        occlusion: vec![true],
        opaque: vec![OpaquePath::Compute],
        lighting: Default::default(),
    };
    let mut scene = SceneSummary {
        adapter: ctx.capabilities.adapter.to_string(),
        side: terrain.side,
        chunk_edge: size.edge(),
        width,
        height,
        frames: config.frames,
        ..Default::default()
    };
    let (runs, _, _) =
        run(&ctx, &terrain, &config, &mut scene).map_err(|e| ReportError(e.to_string()))?;
    let json = serde_json::to_string(&BenchReport { scene, runs })
        .map_err(|e| ReportError(format!("lavapipe sweep: {e}")))?;
    parse(&json, "measured in this run").map(Some)
}
