//! Picking the block under a ray from the camera: a voxel walk (Amanatides and Woo) through
//! the edited world, up to a reach, returning the first non-air block and the air cell in
//! front of it (where a placed block goes).

use glam::DVec3;
use voxel_core::{BlockId, WorldPos};
use voxel_scene::Terrain;
use voxel_world::World;

/// What a ray hit.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Pick {
    /// The first non-air block on the ray (what a break removes).
    pub hit: WorldPos,
    /// Its id.
    pub block: BlockId,
    /// The cell the ray crossed just before it (where a place writes), unless the ray starts
    /// inside the block.
    pub before: Option<WorldPos>,
}

/// The first non-air block of `world` on the ray from `origin` (world blocks) along
/// `direction`, within `reach` blocks; `None` when the ray meets only air, and an error naming
/// the problem for a ray that is not finite, has no direction or starts outside the world, or
/// a base that cannot fill a chunk.
pub fn pick(
    world: &mut World<Terrain>,
    origin: DVec3,
    direction: DVec3,
    reach: f64,
) -> Result<Option<Pick>, String> {
    let bad = |why: &str| format!("picking a block: {why}");
    if !origin.is_finite() || !direction.is_finite() || !reach.is_finite() {
        return Err(bad("the ray's origin, direction or reach is not finite"));
    }
    let length = direction.length();
    if length == 0.0 {
        return Err(bad("the ray's direction is zero"));
    }
    let dir = direction / length;
    let limit = f64::from(i32::MAX) - reach.abs() - 2.0;
    if origin.abs().max_element() > limit {
        return Err(bad("the ray starts outside the world's i32 range"));
    }
    let mut cell = origin.floor();
    let step = dir.signum();
    // Distance along the ray to the next cell boundary per axis, and between boundaries.
    let next = |o: f64, c: f64, d: f64| {
        if d > 0.0 {
            (c + 1.0 - o) / d
        } else if d < 0.0 {
            (o - c) / -d
        } else {
            f64::INFINITY
        }
    };
    let mut t_max = DVec3::new(
        next(origin.x, cell.x, dir.x),
        next(origin.y, cell.y, dir.y),
        next(origin.z, cell.z, dir.z),
    );
    let t_delta = DVec3::new(1.0 / dir.x.abs(), 1.0 / dir.y.abs(), 1.0 / dir.z.abs());
    let mut before = None;
    let mut t = 0.0;
    while t <= reach {
        let pos = WorldPos::new(cell.x as i32, cell.y as i32, cell.z as i32);
        let block = world
            .block(pos)
            .map_err(|e| format!("picking a block: {e}"))?;
        if !block.is_air() {
            return Ok(Some(Pick {
                hit: pos,
                block,
                before,
            }));
        }
        before = Some(pos);
        // Step along the axis whose boundary comes first.
        if t_max.x <= t_max.y && t_max.x <= t_max.z {
            t = t_max.x;
            t_max.x += t_delta.x;
            cell.x += step.x;
        } else if t_max.y <= t_max.z {
            t = t_max.y;
            t_max.y += t_delta.y;
            cell.y += step.y;
        } else {
            t = t_max.z;
            t_max.z += t_delta.z;
            cell.z += step.z;
        }
    }
    Ok(None)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::edits::SharedWorld;
    use voxel_core::ChunkSize;
    use voxel_world::Edit;

    #[test]
    fn a_ray_down_hits_the_ground_and_a_placed_block_goes_in_front() {
        let world = SharedWorld::new(1, ChunkSize::S16, 2).unwrap();
        let mut w = world.write();
        let ground = w.base().height(3, 7);
        let top = WorldPos::new(3, ground, 7);
        let origin = DVec3::new(3.5, f64::from(ground) + 10.5, 7.5);
        let p = pick(&mut w, origin, DVec3::NEG_Y, 64.0).unwrap().unwrap();
        assert_eq!(p.hit, top);
        assert_eq!(p.before, Some(WorldPos::new(3, ground + 1, 7)));
        assert!(!p.block.is_air());
        // Break it: the next pick goes one deeper (or into a cave below).
        w.apply(&[Edit::Block {
            pos: top,
            id: BlockId::AIR,
        }])
        .unwrap();
        let q = pick(&mut w, origin, DVec3::NEG_Y, 64.0).unwrap().unwrap();
        assert!(q.hit.y < ground, "{q:?}");
        // Out of reach: nothing.
        assert_eq!(pick(&mut w, origin, DVec3::NEG_Y, 5.0).unwrap(), None);
        // A slanted ray enters the ground through a face the walk crossed.
        let s = pick(&mut w, origin, DVec3::new(0.3, -1.0, 0.2), 64.0)
            .unwrap()
            .unwrap();
        let b = s.before.unwrap();
        let manhattan = (s.hit.x - b.x).abs() + (s.hit.y - b.y).abs() + (s.hit.z - b.z).abs();
        assert_eq!(manhattan, 1, "{s:?}");
    }

    #[test]
    fn bad_rays_are_refused_by_name() {
        let world = SharedWorld::new(1, ChunkSize::S16, 2).unwrap();
        let mut w = world.write();
        let e = pick(&mut w, DVec3::ZERO, DVec3::ZERO, 10.0).unwrap_err();
        assert!(e.contains("direction is zero"), "{e}");
        let e = pick(&mut w, DVec3::NAN, DVec3::Y, 10.0).unwrap_err();
        assert!(e.contains("not finite"), "{e}");
        let e = pick(&mut w, DVec3::splat(3e9), DVec3::Y, 10.0).unwrap_err();
        assert!(e.contains("i32 range"), "{e}");
    }
}
