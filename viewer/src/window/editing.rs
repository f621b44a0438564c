//! Editing the streamed terrain in the window: a click (a press and release without a drag)
//! picks the block under the cursor by a ray through the world; the left button breaks the
//! brush there, the right places it in front of the picked face. `[` and `]` change the brush
//! radius (0: one block), 1 to 6 its block (grass, dirt, stone, sand, water, snow). With a
//! world folder the edits are saved every [`AUTOSAVE`] and when the window closes.

use std::path::PathBuf;
use std::time::{Duration, Instant};

use voxel_core::BlockId;
use voxel_scene::TerrainBlocks;
use voxel_world::Edit;

use crate::edits::{SharedWorld, pick};
use crate::stream::StreamError;
use crate::view::StreamedView;
use render_model::camera::Camera;

/// How often the window saves a world with unsaved edits.
pub const AUTOSAVE: Duration = Duration::from_secs(30);

/// How far a click reaches, blocks.
pub const REACH: f64 = 256.0;

/// The largest brush radius, blocks.
pub const MAX_BRUSH: u32 = 16;

/// What a click writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Brush {
    /// 0: one block; else a sphere of this radius.
    pub radius: u32,
    /// The block a right click places.
    pub block: BlockId,
}

impl Default for Brush {
    fn default() -> Brush {
        Brush {
            radius: 0,
            block: TerrainBlocks::palette().1.stone,
        }
    }
}

impl Brush {
    /// The brush one step larger (`grow`) or smaller, within `0..=MAX_BRUSH`.
    pub fn resized(self, grow: bool) -> Brush {
        let radius = if grow {
            (self.radius + 1).min(MAX_BRUSH)
        } else {
            self.radius.saturating_sub(1)
        };
        Brush { radius, ..self }
    }

    /// The brush with block `n` (1 to 6: grass, dirt, stone, sand, water, snow), or itself.
    pub fn with_block(self, n: u32) -> Brush {
        let b = TerrainBlocks::palette().1;
        let block = match n {
            1 => b.grass,
            2 => b.dirt,
            3 => b.stone,
            4 => b.sand,
            5 => b.water,
            6 => b.snow,
            _ => return self,
        };
        Brush { block, ..self }
    }

    /// The brush's edit at `pos`, writing `id`.
    fn edit(self, pos: voxel_core::WorldPos, id: BlockId) -> Edit {
        if self.radius == 0 {
            Edit::Block { pos, id }
        } else {
            Edit::Sphere {
                centre: pos,
                radius: self.radius,
                id,
            }
        }
    }
}

/// Breaks (`place` false) or places the brush at the block under pixel `(px, py)` of a
/// `width x height` frame of `camera`. Returns a line for the overlay (what was edited, or
/// that the ray met only air).
pub fn click(
    view: &mut StreamedView,
    camera: &Camera,
    (px, py): (u32, u32),
    (width, height): (u32, u32),
    brush: Brush,
    place: bool,
) -> Result<String, StreamError> {
    let v = camera.voxel;
    let origin = glam::DVec3::new(f64::from(v.x), f64::from(v.y), f64::from(v.z)) + camera.fraction;
    let direction = camera.ray_direction(px, py, width, height);
    let hit = {
        let mut world = view.world().write();
        pick(&mut world, origin, direction, REACH).map_err(StreamError::Edit)?
    };
    let Some(hit) = hit else {
        return Ok(format!("nothing within {REACH} blocks under the cursor"));
    };
    let (pos, id) = match (place, hit.before) {
        (false, _) => (hit.hit, BlockId::AIR),
        (true, Some(before)) => (before, brush.block),
        (true, None) => return Ok("the camera is inside a block: nothing placed".to_owned()),
    };
    let done = view.apply_edits(&[brush.edit(pos, id)])?;
    Ok(format!(
        "{} at ({}, {}, {}), radius {}: {} nodes swapped, {} rebuilding",
        if place { "placed" } else { "broke" },
        pos.x,
        pos.y,
        pos.z,
        brush.radius,
        done.swapped,
        done.queued
    ))
}

/// The world folder of `--world` and when it was last saved.
#[derive(Debug)]
pub struct Autosave {
    dir: PathBuf,
    last: Instant,
}

impl Autosave {
    /// Saves into `dir`.
    pub fn new(dir: PathBuf) -> Autosave {
        Autosave {
            dir,
            last: Instant::now(),
        }
    }

    /// Saves `world` when it has unsaved edits and [`AUTOSAVE`] passed (or `now_anyway`):
    /// a line saying what was saved, or the error naming the folder.
    pub fn tick(
        &mut self,
        world: &SharedWorld,
        now_anyway: bool,
    ) -> Result<Option<String>, String> {
        if !world.unsaved() || (!now_anyway && self.last.elapsed() < AUTOSAVE) {
            return Ok(None);
        }
        self.last = Instant::now();
        let chunks = world
            .save(&self.dir)
            .map_err(|e| format!("saving the world to {}: {e}", self.dir.display()))?;
        Ok(Some(format!(
            "saved {chunks} region files to {}",
            self.dir.display()
        )))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn autosave_saves_unsaved_edits_when_due_and_names_a_bad_folder() {
        let world = SharedWorld::new(1, voxel_core::ChunkSize::S16, 2).unwrap();
        let dir = tempfile::tempdir().unwrap();
        let mut autosave = Autosave::new(dir.path().join("world"));
        assert_eq!(autosave.tick(&world, true), Ok(None), "nothing to save");
        world
            .apply(&[Edit::Block {
                pos: voxel_core::WorldPos::new(0, 60, 0),
                id: TerrainBlocks::palette().1.stone,
            }])
            .unwrap();
        assert_eq!(autosave.tick(&world, false), Ok(None), "not due yet");
        let line = autosave.tick(&world, true).unwrap().unwrap();
        assert!(line.contains("saved 1 region files"), "{line}");
        assert!(!world.unsaved());
        let (again, report) =
            SharedWorld::load(&dir.path().join("world"), 1, voxel_core::ChunkSize::S16, 2).unwrap();
        assert_eq!(report.chunks, 1);
        assert_eq!(
            again
                .write()
                .block(voxel_core::WorldPos::new(0, 60, 0))
                .unwrap(),
            TerrainBlocks::palette().1.stone
        );
        // A folder under a file cannot be made: the error names it.
        let file = dir.path().join("file");
        std::fs::write(&file, b"x").unwrap();
        let mut bad = Autosave::new(file.join("world"));
        world
            .apply(&[Edit::Block {
                pos: voxel_core::WorldPos::new(1, 60, 0),
                id: TerrainBlocks::palette().1.stone,
            }])
            .unwrap();
        let e = bad.tick(&world, true).unwrap_err();
        assert!(
            e.contains("saving the world to") && e.contains("file"),
            "{e}"
        );
    }

    #[test]
    fn the_brush_stays_in_range_and_picks_blocks() {
        let b = Brush::default();
        assert_eq!(b.resized(false).radius, 0);
        let mut big = b;
        for _ in 0..40 {
            big = big.resized(true);
        }
        assert_eq!(big.radius, MAX_BRUSH);
        let blocks = TerrainBlocks::palette().1;
        assert_eq!(b.with_block(5).block, blocks.water);
        assert_eq!(b.with_block(9), b);
        let pos = voxel_core::WorldPos::new(1, 2, 3);
        assert_eq!(
            b.edit(pos, BlockId::AIR),
            Edit::Block {
                pos,
                id: BlockId::AIR
            }
        );
        assert!(matches!(
            big.edit(pos, BlockId::AIR),
            Edit::Sphere {
                radius: MAX_BRUSH,
                ..
            }
        ));
    }
}
