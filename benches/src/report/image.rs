//! The image section: the budget sweep of a `gpu_bench --json` file (image error against the
//! full-detail frame, GPU time, bytes), read as the GPU machine wrote it.

use std::path::Path;

use serde_json::Value;

use super::ReportError;

/// Bytes of one packed quad (`PackedQuad`).
const QUAD_BYTES: u64 = 8;
/// Bytes of one far block (`DrawBlock`).
const DRAW_BLOCK_BYTES: u64 = 4;

/// One setting of the sweep: full detail (`budget_px: None`) or an error budget.
#[derive(Clone, Debug, PartialEq)]
pub struct BudgetRow {
    /// The error budget in pixels; `None` for the full-detail frame.
    pub budget_px: Option<f64>,
    /// Median GPU time of the frame, microseconds.
    pub gpu_us: f64,
    /// Median CPU time of the frame, microseconds.
    pub cpu_us: f64,
    /// Mean absolute error against the full-detail frame, in 8-bit steps (`None` for it).
    pub mean_abs: Option<f64>,
    /// Share of pixels off by more than 8/255 in some channel (`None` for full detail).
    pub share_over_8: Option<f64>,
    /// Meshed nodes drawn.
    pub mesh_nodes: u64,
    /// Far-drawn nodes.
    pub far_nodes: u64,
    /// Quads drawn.
    pub mesh_quads: u64,
    /// Far blocks drawn.
    pub far_blocks: u64,
}

impl BudgetRow {
    /// Bytes of geometry the frame reads: 8 per quad drawn plus 4 per far block drawn.
    pub fn drawn_bytes(&self) -> u64 {
        self.mesh_quads * QUAD_BYTES + self.far_blocks * DRAW_BLOCK_BYTES
    }
}

/// The sweep and the scene it ran on.
#[derive(Clone, Debug, PartialEq)]
pub struct BudgetSweep {
    /// The file it was read from.
    pub source: String,
    /// The GPU and driver, as the benchmark printed them.
    pub adapter: String,
    /// Terrain side in columns.
    pub side: u64,
    /// Chunk edge of the benchmark's scene.
    pub chunk_edge: u64,
    /// Frame size.
    pub width: u64,
    /// Frame size.
    pub height: u64,
    /// Bytes resident on the GPU by kind (one resident set serves every setting of the sweep).
    pub resident_bytes: Vec<(String, u64)>,
    /// The settings, in file order.
    pub rows: Vec<BudgetRow>,
}

impl BudgetSweep {
    /// Total resident bytes.
    pub fn resident_total(&self) -> u64 {
        self.resident_bytes.iter().map(|(_, b)| b).sum()
    }

    /// The full-detail row, if the file has one.
    pub fn full(&self) -> Option<&BudgetRow> {
        self.rows.iter().find(|r| r.budget_px.is_none())
    }
}

/// Reads a `gpu_bench --json` file.
pub fn load(path: &Path) -> Result<BudgetSweep, ReportError> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| ReportError(format!("{}: {e}", path.display())))?;
    parse(&text, &path.display().to_string())
}

/// Parses the text of a `gpu_bench --json` file (`source` names it in the report).
pub fn parse(text: &str, source: &str) -> Result<BudgetSweep, ReportError> {
    let bad = |what: &str| ReportError(format!("{source}: {what}"));
    let v: Value = serde_json::from_str(text).map_err(|e| bad(&e.to_string()))?;
    let scene = &v["scene"];
    let u = |x: &Value| x.as_u64().unwrap_or(0);
    let resident_bytes = scene["resident_bytes"]
        .as_array()
        .ok_or_else(|| bad("no scene.resident_bytes"))?
        .iter()
        .filter_map(|kv| Some((kv[0].as_str()?.to_owned(), kv[1].as_u64()?)))
        .collect();
    let rows = v["runs"]
        .as_array()
        .ok_or_else(|| bad("no runs"))?
        .iter()
        .map(|r| BudgetRow {
            budget_px: r["budget_px"].as_f64(),
            gpu_us: r["gpu_total_us"].as_f64().unwrap_or(f64::NAN),
            cpu_us: r["cpu_frame_us"].as_f64().unwrap_or(f64::NAN),
            mean_abs: r["image_error"]["mean_abs"].as_f64(),
            share_over_8: r["image_error"]["share_over_8"].as_f64(),
            mesh_nodes: u(&r["drawn"]["mesh_nodes"]),
            far_nodes: u(&r["drawn"]["far_nodes"]),
            mesh_quads: u(&r["drawn"]["mesh_quads"]),
            far_blocks: u(&r["drawn"]["far_blocks"]),
        })
        .collect();
    Ok(BudgetSweep {
        source: source.to_owned(),
        adapter: scene["adapter"].as_str().unwrap_or("unknown").to_owned(),
        side: u(&scene["side"]),
        chunk_edge: u(&scene["chunk_edge"]),
        width: u(&scene["width"]),
        height: u(&scene["height"]),
        resident_bytes,
        rows,
    })
}
