//! The window's fly camera: WASD + Space/Shift to move, mouse drag to look, scroll for speed.
//!
//! The eye is the stack's [`Camera`]: an `i32` voxel plus a fraction, so it stays exact
//! anywhere in the `i32` world (the GPU renderer splits it into chunk + offset).
//! Movement adds in `f64` and re-splits; positions past the `i32` range stop at its edge.

use glam::DVec3;
use voxel_core::WorldPos;

use render_model::camera::Camera;

/// Which movement keys are held.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct MoveKeys {
    /// W: along the view direction.
    pub forward: bool,
    /// S: against the view direction.
    pub back: bool,
    /// A: to the left.
    pub left: bool,
    /// D: to the right.
    pub right: bool,
    /// Space: world up.
    pub up: bool,
    /// Shift: world down.
    pub down: bool,
}

impl MoveKeys {
    /// The wished direction in camera terms: (right, up, forward), each -1, 0 or 1.
    fn axes(&self) -> (f64, f64, f64) {
        let axis = |plus: bool, minus: bool| f64::from(i8::from(plus) - i8::from(minus));
        (
            axis(self.right, self.left),
            axis(self.up, self.down),
            axis(self.forward, self.back),
        )
    }
}

/// A free-flying camera (see the [module docs](self)).
#[derive(Clone, Debug, PartialEq)]
pub struct FlyCamera {
    /// The eye and view direction.
    pub eye: Camera,
    /// Movement speed, blocks per second.
    pub speed: f64,
}

impl FlyCamera {
    /// Slowest speed, blocks per second.
    pub const MIN_SPEED: f64 = 0.5;
    /// Fastest speed, blocks per second.
    pub const MAX_SPEED: f64 = 4096.0;
    /// Radians of turn per pixel of mouse drag.
    pub const LOOK_PER_PIXEL: f64 = 0.004;
    /// Pitch limit (just short of straight up or down, where yaw is undefined).
    pub const MAX_PITCH: f64 = 89.0 * std::f64::consts::PI / 180.0;
    /// Speed factor per scroll line.
    pub const SCROLL_FACTOR: f64 = 1.2;

    /// A camera at `eye` moving at `speed` blocks per second.
    pub fn new(eye: Camera, speed: f64) -> FlyCamera {
        FlyCamera {
            eye,
            speed: clamp_speed(speed),
        }
    }

    /// Moves for `seconds` with `keys` held. Non-finite or negative times do nothing.
    pub fn step(&mut self, keys: &MoveKeys, seconds: f64) {
        if !(seconds.is_finite() && seconds > 0.0) {
            return;
        }
        let (right, up, forward) = keys.axes();
        let basis = self.eye.basis();
        let dir =
            DVec3::from(basis.forward) * forward + DVec3::from(basis.right) * right + DVec3::Y * up;
        if dir == DVec3::ZERO {
            return;
        }
        self.translate(dir.normalize() * self.speed * seconds);
    }

    /// Moves the eye by `delta` blocks, stopping at the edge of the `i32` world.
    pub fn translate(&mut self, delta: DVec3) {
        if !delta.is_finite() {
            return;
        }
        let v = self.eye.voxel;
        let pos =
            DVec3::new(f64::from(v.x), f64::from(v.y), f64::from(v.z)) + self.eye.fraction + delta;
        let lo = f64::from(i32::MIN);
        let hi = f64::from(i32::MAX);
        let floor = pos.floor().clamp(DVec3::splat(lo), DVec3::splat(hi));
        // In range after the clamp, so the casts are exact.
        self.eye.voxel = WorldPos::new(floor.x as i32, floor.y as i32, floor.z as i32);
        // Just below 1: the fraction must stay inside its voxel.
        let below_one = 1.0 - f64::EPSILON;
        self.eye.fraction = (pos - floor).clamp(DVec3::ZERO, DVec3::splat(below_one));
    }

    /// Turns by a mouse drag of `(dx, dy)` pixels (right turns right, up looks up).
    pub fn look(&mut self, dx: f64, dy: f64) {
        if !(dx.is_finite() && dy.is_finite()) {
            return;
        }
        let tau = std::f64::consts::TAU;
        self.eye.yaw = (self.eye.yaw - dx * Self::LOOK_PER_PIXEL).rem_euclid(tau);
        self.eye.pitch =
            (self.eye.pitch - dy * Self::LOOK_PER_PIXEL).clamp(-Self::MAX_PITCH, Self::MAX_PITCH);
    }

    /// Changes the speed by `lines` scroll lines (up is faster).
    pub fn scroll(&mut self, lines: f64) {
        if lines.is_finite() {
            self.speed = clamp_speed(self.speed * Self::SCROLL_FACTOR.powf(lines));
        }
    }

    /// The camera at the eye.
    pub fn camera(&self) -> Camera {
        self.eye
    }

    /// The eye's world position, blocks (for display).
    pub fn position(&self) -> DVec3 {
        let v = self.eye.voxel;
        DVec3::new(f64::from(v.x), f64::from(v.y), f64::from(v.z)) + self.eye.fraction
    }
}

fn clamp_speed(speed: f64) -> f64 {
    if speed.is_nan() {
        FlyCamera::MIN_SPEED
    } else {
        // Infinities clamp to the ends too.
        speed.clamp(FlyCamera::MIN_SPEED, FlyCamera::MAX_SPEED)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn camera() -> FlyCamera {
        FlyCamera::new(
            Camera {
                voxel: WorldPos::new(0, 10, 0),
                fraction: DVec3::splat(0.5),
                yaw: 0.0,
                pitch: 0.0,
                fov_y: 1.0,
                near: Camera::DEFAULT_NEAR,
            },
            10.0,
        )
    }

    #[test]
    fn forward_at_yaw_zero_is_minus_z_and_keys_combine() {
        let mut c = camera();
        let keys = MoveKeys {
            forward: true,
            ..MoveKeys::default()
        };
        c.step(&keys, 1.0);
        let p = c.position();
        assert!((p - DVec3::new(0.5, 10.5, -9.5)).length() < 1e-9, "{p}");
        let mut c = camera();
        let keys = MoveKeys {
            right: true,
            up: true,
            ..MoveKeys::default()
        };
        c.step(&keys, 1.0);
        let moved = c.position() - DVec3::new(0.5, 10.5, 0.5);
        assert!(
            (moved.length() - 10.0).abs() < 1e-9,
            "diagonal speed is the speed"
        );
        assert!(
            moved.x > 0.0 && moved.y > 0.0 && moved.z.abs() < 1e-9,
            "{moved}"
        );
    }

    #[test]
    fn dragging_right_turns_right_and_pitch_is_clamped() {
        let mut c = camera();
        c.look(100.0, 0.0);
        let forward = c.camera().basis().forward;
        assert!(forward[0] > 0.0, "turned towards +x: {forward:?}");
        c.look(0.0, -1e6);
        assert_eq!(c.eye.pitch, FlyCamera::MAX_PITCH);
        c.look(f64::NAN, 1.0);
        assert_eq!(c.eye.pitch, FlyCamera::MAX_PITCH, "NaN ignored");
    }

    #[test]
    fn the_eye_stops_at_the_edge_of_the_world_and_stays_in_its_voxel() {
        let mut c = camera();
        c.translate(DVec3::new(1e12, -1e12, f64::INFINITY));
        c.translate(DVec3::new(1e12, -1e12, 0.0));
        assert_eq!(c.eye.voxel, WorldPos::new(i32::MAX, i32::MIN, 0));
        assert!(c.eye.fraction.cmpge(DVec3::ZERO).all() && c.eye.fraction.cmplt(DVec3::ONE).all());
        let mut c = camera();
        c.translate(DVec3::new(-0.75, 0.25, 0.0));
        assert_eq!(c.eye.voxel, WorldPos::new(-1, 10, 0));
        assert!((c.eye.fraction - DVec3::new(0.75, 0.75, 0.5)).length() < 1e-12);
    }

    #[test]
    fn scrolling_scales_speed_within_limits() {
        let mut c = camera();
        c.scroll(1.0);
        assert!((c.speed - 12.0).abs() < 1e-9);
        c.scroll(1e9);
        assert_eq!(c.speed, FlyCamera::MAX_SPEED);
        c.scroll(-1e9);
        assert_eq!(c.speed, FlyCamera::MIN_SPEED);
    }
}
