//! The order blended (glTF `BLEND`) props are drawn in.
//!
//! Blended props are drawn after the opaque image is lit (and after the voxels' transparent
//! layer), into the lit colour, depth-tested against the opaque depth and not writing it, so
//! what is behind them shows through and they never hide one another's depth. Their order:
//!
//! - **batches back to front**, by the distance from the eye to the centre of the batch's
//!   nearest shown instance's bounding sphere ([`instance_sphere`]), the farthest first; ties
//!   by batch index;
//! - **within a batch**, instances in the cull's order (not sorted: the cull appends them
//!   concurrently), each instance's triangles in index order.
//!
//! The limits: two blended instances of one batch that overlap on screen may composite in
//! either order (and the order may change from frame to frame); two batches whose instances
//! interleave in depth composite by their nearest instances only; a blended prop behind the
//! voxels' transparent layer (under water) is drawn over it. The CPU cost is one distance per
//! shown instance of a blended batch per frame (opaque and masked props cost nothing here).

use super::{PropBatchRecord, PropEye, PropInstanceRecord, instance_sphere};

/// The batches of `batches` whose material `blended` says is `BLEND` and that show an
/// instance, back to front (see the [module docs](self)), as batch indices; `instances` are
/// the registry's instance records, `eye` the camera's.
pub fn blend_order(
    batches: &[PropBatchRecord],
    instances: &[PropInstanceRecord],
    eye: &PropEye,
    blended: impl Fn(u32) -> bool,
) -> Vec<u32> {
    let mut keyed: Vec<(f32, u32)> = batches
        .iter()
        .enumerate()
        .filter(|(_, b)| b.visible_count > 0 && blended(b.material))
        .filter_map(|(i, b)| {
            let first = b.args.first_instance as usize;
            let shown = instances.get(first..first + b.visible_count as usize)?;
            let nearest = shown
                .iter()
                .map(|r| {
                    let (c, _) = instance_sphere(r, b, eye);
                    (c[0] * c[0] + c[1] * c[1] + c[2] * c[2]).sqrt()
                })
                .fold(f32::INFINITY, f32::min);
            Some((nearest, i as u32))
        })
        .collect();
    keyed.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)));
    keyed.into_iter().map(|(_, i)| i).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cull::DrawIndexedArgs;
    use crate::props::PropPlacement;

    fn record(x: i32) -> PropInstanceRecord {
        let identity = [
            [1.0, 0.0, 0.0, 0.0],
            [0.0, 1.0, 0.0, 0.0],
            [0.0, 0.0, 1.0, 0.0],
            [0.0, 0.0, 0.0, 1.0],
        ];
        PropPlacement::new(voxel_core::WorldPos::new(x, 0, 0), identity)
            .unwrap()
            .record(0)
    }

    fn batch(first: u32, shown: u32, material: u32) -> PropBatchRecord {
        PropBatchRecord {
            args: DrawIndexedArgs {
                first_instance: first,
                ..Default::default()
            },
            visible_count: shown,
            live_count: shown,
            material,
            ..Default::default()
        }
    }

    #[test]
    fn blended_batches_go_back_to_front_by_their_nearest_instance() {
        // Slots: batch 0 at x = 10 and 40, batch 1 at 30, batch 2 (opaque) at 50, batch 3 at
        // 20 and hidden, batch 4 at 30 (a tie with batch 1).
        let instances = [10, 40, 30, 50, 20, 30].map(record);
        let batches = [
            batch(0, 2, 1),
            batch(2, 1, 1),
            batch(3, 1, 0),
            batch(4, 0, 1),
            batch(5, 1, 1),
        ];
        let eye = PropEye {
            voxel: [0, 0, 0],
            fraction: [0.0; 3],
        };
        let order = blend_order(&batches, &instances, &eye, |m| m == 1);
        assert_eq!(
            order,
            [1, 4, 0],
            "30, 30 (by index), then the batch nearest at 10"
        );
        // From x = 60: batch 0's nearest (at 40) is 20 away, batches 1 and 4 are 30 away.
        let eye = PropEye {
            voxel: [60, 0, 0],
            fraction: [0.0; 3],
        };
        assert_eq!(
            blend_order(&batches, &instances, &eye, |m| m == 1),
            [1, 4, 0]
        );
        let eye = PropEye {
            voxel: [25, 0, 0],
            fraction: [0.0; 3],
        };
        // From 25: batch 0's nearest is 15 away, batches 1 and 4 are 5 away.
        assert_eq!(
            blend_order(&batches, &instances, &eye, |m| m == 1),
            [0, 1, 4]
        );
    }
}
