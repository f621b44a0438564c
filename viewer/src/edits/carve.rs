//! The flight's carving (`--edits-per-second N`): spheres of air at the ground ahead of the
//! camera, a fixed number per second of flight, at positions drawn from a fixed seed, so
//! every run makes the same edits.

use glam::DVec3;
use voxel_core::{BlockId, WorldPos};
use voxel_scene::Terrain;
use voxel_world::Edit;

/// Makes the edits of each frame of a flight (see the [module docs](self)).
#[derive(Clone, Debug)]
pub struct Carver {
    per_frame: f64,
    owed: f64,
    radius: u32,
    state: u64,
}

impl Carver {
    /// The radius of the flight's spheres, blocks.
    pub const RADIUS: u32 = 4;
    /// Spheres land this many blocks ahead of the camera, horizontally, at the nearest...
    pub const NEAREST: f64 = 12.0;
    /// ... and at the farthest.
    pub const FARTHEST: f64 = 96.0;
    /// Spheres land at most this many blocks to either side of the heading.
    pub const SIDE: f64 = 40.0;

    /// `per_second` spheres of [`RADIUS`](Self::RADIUS) per second of flight at `hz` frames
    /// per second; an error for a rate that is negative or not finite.
    pub fn new(per_second: f64, hz: f64) -> Result<Carver, String> {
        if !per_second.is_finite() || per_second < 0.0 || !hz.is_finite() || hz <= 0.0 {
            return Err(format!(
                "edits per second must be a finite number >= 0 (got {per_second})"
            ));
        }
        Ok(Carver {
            per_frame: per_second / hz,
            owed: 0.0,
            radius: Self::RADIUS,
            state: 0x9E37_79B9_7F4A_7C15,
        })
    }

    /// The edits of the next frame, for a camera at `eye` heading along `yaw` over `terrain`.
    pub fn next_frame(&mut self, eye: DVec3, yaw: f64, terrain: &Terrain) -> Vec<Edit> {
        self.owed += self.per_frame;
        let count = self.owed.floor();
        self.owed -= count;
        let forward = DVec3::new(-yaw.sin(), 0.0, -yaw.cos());
        let side = DVec3::new(forward.z, 0.0, -forward.x);
        (0..count as usize)
            .map(|_| {
                let ahead = Self::NEAREST + self.unit() * (Self::FARTHEST - Self::NEAREST);
                let across = (self.unit() * 2.0 - 1.0) * Self::SIDE;
                let p = eye + forward * ahead + side * across;
                let (x, z) = (p.x.floor() as i32, p.z.floor() as i32);
                let y = terrain.height(x, z).max(terrain.sea_level);
                Edit::Sphere {
                    centre: WorldPos::new(x, y, z),
                    radius: self.radius,
                    id: BlockId::AIR,
                }
            })
            .collect()
    }

    /// A number in `0..1` from the carver's generator (splitmix64).
    fn unit(&mut self) -> f64 {
        self.state = self.state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        (z >> 11) as f64 / (1u64 << 53) as f64
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use voxel_scene::TerrainBlocks;

    #[test]
    fn the_rate_is_kept_over_frames_and_runs_repeat() {
        let terrain = Terrain::new(1, TerrainBlocks::palette().1);
        let mut a = Carver::new(1000.0, 60.0).unwrap();
        let mut b = Carver::new(1000.0, 60.0).unwrap();
        let eye = DVec3::new(0.5, 80.0, 0.5);
        let mut total = 0;
        for _ in 0..60 {
            let edits = a.next_frame(eye, 0.3, &terrain);
            assert_eq!(edits, b.next_frame(eye, 0.3, &terrain));
            assert!((16..=17).contains(&edits.len()), "{}", edits.len());
            for e in &edits {
                let Edit::Sphere { centre, radius, id } = *e else {
                    panic!("{e:?}")
                };
                assert_eq!((radius, id), (Carver::RADIUS, BlockId::AIR));
                let d = DVec3::new(f64::from(centre.x), eye.y, f64::from(centre.z)) - eye;
                assert!(d.length() <= Carver::FARTHEST + Carver::SIDE + 2.0, "{d}");
            }
            total += edits.len();
        }
        assert_eq!(total, 1000);
        assert!(Carver::new(-1.0, 60.0).is_err());
        assert!(Carver::new(f64::NAN, 60.0).is_err());
        assert!(
            Carver::new(0.0, 60.0)
                .unwrap()
                .next_frame(eye, 0.0, &terrain)
                .is_empty()
        );
    }
}
