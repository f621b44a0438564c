//! Numbers at the extremes: the same small terrain view rendered by the CPU reference
//! raycaster (`viewer::reference_raycast`) with the camera and the world at the origin and
//! moved together by ±2^30 voxels; the pixel difference between the frames.

use glam::DVec3;
use render_model::camera::Camera;
use render_model::lighting::Lighting;
use voxel_core::WorldPos;
use voxel_reference::deferred_reference::render_deferred as render;
use voxel_scene::{Terrain, TerrainBlocks};

/// Farthest a ray travels, voxels.
const MAX_DISTANCE: f64 = 160.0;

/// The offsets the view is moved by, besides the origin.
pub const OFFSETS: [[i32; 3]; 4] = [
    [1 << 30, 1 << 30, 1 << 30],
    [-(1 << 30), -(1 << 30), -(1 << 30)],
    [1 << 30, 0, -(1 << 30)],
    [i32::MAX - 256, 1 << 30, i32::MIN + 256],
];

/// The difference between the frame at one offset and the frame at the origin.
#[derive(Clone, Debug, PartialEq)]
pub struct ExtremeRow {
    /// The offset in voxels.
    pub offset: [i32; 3],
    /// Pixels whose colour differs at all.
    pub pixels_differing: usize,
    /// Pixels in the frame.
    pub pixels: usize,
    /// Largest difference of one channel, 8-bit steps.
    pub max_channel_diff: u8,
    /// Mean absolute difference over every RGB channel, 8-bit steps.
    pub mean_abs: f64,
    /// Share of the frame that is terrain (not sky) at the origin: a blank view would prove
    /// nothing.
    pub terrain_share: f64,
}

/// Renders the view at the origin and at every offset of [`OFFSETS`], `size` pixels.
pub fn measure(seed: i32, size: (u32, u32)) -> Vec<ExtremeRow> {
    let (palette, blocks) = TerrainBlocks::palette();
    let terrain = Terrain::new(seed, blocks);
    let ground = terrain.height(0, 0);
    let frame = |off: [i32; 3]| {
        let camera = Camera {
            voxel: WorldPos {
                x: off[0],
                y: off[1].wrapping_add(ground + 10),
                z: off[2],
            },
            fraction: DVec3::new(0.37, 0.5, 0.61),
            yaw: 0.6,
            pitch: -0.3,
            fov_y: 60f64.to_radians(),
            near: Camera::DEFAULT_NEAR,
        };
        let block_at = |p: WorldPos| {
            terrain.block_at(
                p.x.wrapping_sub(off[0]),
                p.y.wrapping_sub(off[1]),
                p.z.wrapping_sub(off[2]),
            )
        };
        render(
            &block_at,
            &palette,
            &camera,
            &Lighting::default(),
            size.0,
            size.1,
            MAX_DISTANCE,
        )
    };
    let origin = frame([0, 0, 0]);
    let pixels = origin.depth.len();
    let terrain_share =
        origin.depth.iter().filter(|d| d.is_finite()).count() as f64 / pixels.max(1) as f64;
    OFFSETS
        .iter()
        .map(|&offset| {
            let img = frame(offset);
            let mut differing = 0;
            let mut max = 0u8;
            let mut sum = 0u64;
            for (a, b) in origin.rgba.chunks_exact(4).zip(img.rgba.chunks_exact(4)) {
                let d: Vec<u8> = (0..3).map(|c| a[c].abs_diff(b[c])).collect();
                if d.iter().any(|&x| x > 0) {
                    differing += 1;
                }
                max = max.max(d.iter().copied().max().unwrap_or(0));
                sum += d.iter().map(|&x| u64::from(x)).sum::<u64>();
            }
            ExtremeRow {
                offset,
                pixels_differing: differing,
                pixels,
                max_channel_diff: max,
                mean_abs: sum as f64 / (3 * pixels.max(1)) as f64,
                terrain_share,
            }
        })
        .collect()
}
