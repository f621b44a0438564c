//! `gpu_bench --props N`: N instances of a sample prop (the Duck: no Draco needed) on a grid
//! seen at an angle, drawn by the deferred renderer with occlusion culling; per setting the
//! prop cull and prop draw GPU times (medians), the instances the cull kept (read back), and
//! the CPU time per frame of recording and submitting it (thread CPU time, median), at N and
//! at N / 100: the CPU figure does not depend on N (one cull dispatch, one indirect draw per
//! batch).

use std::path::Path;

use glam::DVec3;
use gpu_backend::GpuContext;
use gpu_backend::render::{Renderer, RendererConfig};
use render_model::props::PropPlacement;
use render_model::{Camera, Lighting};
use voxel_core::{ChunkSize, Material, MaterialPalette, WorldPos};
use voxel_scene::props::{PropLimits, load_prop_file};

use crate::cpu_time::thread_cpu_now;

/// One measured prop setting.
#[derive(Clone, Debug, PartialEq)]
pub struct PropFigures {
    /// Instances placed.
    pub instances: u32,
    /// Instances the last frame's cull kept.
    pub drawn: u64,
    /// Median GPU time of the prop cull, ms.
    pub cull_ms: f64,
    /// Median GPU time of the prop draw, ms.
    pub draw_ms: f64,
    /// Median CPU time per frame (recording and submitting), ms.
    pub cpu_ms: f64,
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v.get(v.len() / 2).copied().unwrap_or(f64::NAN)
}

/// Measures `instances` props of `file` at `width x height` over `frames` frames.
pub fn bench_props(
    ctx: &GpuContext,
    file: &Path,
    instances: u32,
    (width, height): (u32, u32),
    frames: usize,
) -> Result<PropFigures, Box<dyn std::error::Error>> {
    let model = load_prop_file(file, &PropLimits::default())?;
    let mut palette = MaterialPalette::new();
    palette.push(Material::opaque(120, 120, 130))?;
    let mut config = RendererConfig::new(width, height, ChunkSize::S16);
    config.occlusion = true;
    let mut renderer = Renderer::new(ctx, &config, &palette)?;
    renderer.set_lighting(&Lighting::default())?;
    let id = renderer.add_prop_model(&model)?;
    // A square grid, 3 blocks apart, centred on the origin.
    let side = (f64::from(instances)).sqrt().ceil() as i32;
    let identity = [
        [1.0, 0.0, 0.0, 0.0],
        [0.0, 1.0, 0.0, 0.0],
        [0.0, 0.0, 1.0, 0.0],
        [0.0, 0.0, 0.0, 1.0],
    ];
    for i in 0..instances as i32 {
        let (x, z) = ((i % side - side / 2) * 3, (i / side - side / 2) * 3);
        renderer.create_prop(id, PropPlacement::new(WorldPos::new(x, 0, z), identity)?)?;
    }
    let reach = f64::from(side) * 1.5;
    let eye = DVec3::new(0.0, reach * 0.5 + 4.0, reach + 8.0);
    let d = (DVec3::ZERO - eye).normalize();
    let floor = eye.floor();
    renderer.set_camera(&Camera::new(
        WorldPos::new(floor.x as i32, floor.y as i32, floor.z as i32),
        eye - floor,
        (-d.x).atan2(-d.z),
        d.y.asin(),
        1.0,
    ));
    // Warm-up: the first frame uploads every record.
    renderer.render()?;
    let (mut cull, mut draw, mut cpu) = (Vec::new(), Vec::new(), Vec::new());
    for _ in 0..frames {
        let start = thread_cpu_now();
        let mut encoder = ctx.device.create_command_encoder(&Default::default());
        renderer.record_frame(&mut encoder)?;
        renderer.submit_frame(encoder);
        cpu.push((thread_cpu_now() - start).as_secs_f64() * 1e3);
        let times = renderer.collect_timings()?;
        let ms = |label: &str| {
            times
                .iter()
                .filter(|t| t.label == label)
                .map(|t| t.nanoseconds as f64 / 1e6)
                .sum::<f64>()
        };
        cull.push(ms("prop cull"));
        draw.push(ms("props"));
    }
    Ok(PropFigures {
        instances,
        drawn: renderer.read_props_drawn()?,
        cull_ms: median(cull),
        draw_ms: median(draw),
        cpu_ms: median(cpu),
    })
}
