//! The registry against a naive model, the dirty ranges against a mirrored GPU copy, the
//! camera-relative rule at a far origin, and the cull twin's decisions.

use std::collections::BTreeMap;

use glam::DVec3;
use proptest::prelude::*;
use voxel_core::WorldPos;

use super::*;
use crate::Camera;
use crate::hiz::pyramid_reference;

const IDENTITY: [[f32; 4]; 4] = [
    [1.0, 0.0, 0.0, 0.0],
    [0.0, 1.0, 0.0, 0.0],
    [0.0, 0.0, 1.0, 0.0],
    [0.0, 0.0, 0.0, 1.0],
];

fn at(x: i32, y: i32, z: i32) -> PropPlacement {
    PropPlacement::new(WorldPos::new(x, y, z), IDENTITY).unwrap()
}

fn unit_primitive(registry: &mut PropRegistry, first_index: u32) -> PrimitiveId {
    registry.add_primitive(PropPrimitiveDesc {
        index_count: 36,
        first_index,
        base_vertex: 0,
        sphere_centre: [0.0; 3],
        sphere_radius: 0.5,
    })
}

#[derive(Clone, Debug)]
enum Op {
    Create {
        primitive: u8,
        material: u8,
        x: i8,
        visible: bool,
    },
    Delete(u8),
    Move(u8, i8),
    Show(u8, bool),
    DeleteStale(u8),
}

fn op() -> impl Strategy<Value = Op> {
    prop_oneof![
        4 => (0u8..3, 0u8..2, any::<i8>(), any::<bool>()).prop_map(|(primitive, material, x, visible)| Op::Create { primitive, material, x, visible }),
        2 => any::<u8>().prop_map(Op::Delete),
        2 => (any::<u8>(), any::<i8>()).prop_map(|(i, x)| Op::Move(i, x)),
        2 => (any::<u8>(), any::<bool>()).prop_map(|(i, v)| Op::Show(i, v)),
        1 => any::<u8>().prop_map(Op::DeleteStale),
    ]
}

/// The registry's state agrees with the naive model, and the mirror made from the uploads
/// equals the registry's records.
fn check(
    registry: &PropRegistry,
    model: &BTreeMap<PropHandle, (u32, u32, PropPlacement, bool)>,
    primitives: &[PrimitiveId],
    mirror: &mut (Vec<PropInstanceRecord>, Vec<PropBatchRecord>),
    upload: &PropUpload,
) {
    // Apply the upload to the mirror.
    if upload.full {
        mirror.0 = vec![PropInstanceRecord::EMPTY; registry.slot_count() as usize];
        mirror.1 = vec![PropBatchRecord::default(); registry.batch_count() as usize];
    }
    for r in &upload.instances {
        let (s, e) = (r.start as usize, r.end as usize);
        mirror.0[s..e].copy_from_slice(&registry.instance_records()[s..e]);
    }
    for r in &upload.batches {
        let (s, e) = (r.start as usize, r.end as usize);
        mirror.1[s..e].copy_from_slice(&registry.batch_records()[s..e]);
    }
    assert_eq!(mirror.0, registry.instance_records(), "instance mirror");
    assert_eq!(mirror.1, registry.batch_records(), "batch mirror");

    let records = registry.instance_records();
    let batches = registry.batch_records();
    assert_eq!(registry.len(), model.len());
    // Every live handle sits in its batch's range, shown ones in the shown part.
    let mut per_batch = vec![(0u32, 0u32); batches.len()];
    for (&h, &(prim, material, placement, visible)) in model {
        let (p, v, slot) = registry.get(h).expect("live handle");
        assert_eq!((p, v), (placement, visible));
        let record = records[slot as usize];
        assert_eq!(record, placement.record(record.batch));
        let b = &batches[record.batch as usize];
        assert_eq!(b.material, material);
        assert_eq!(b.args.first_index, prim * 100);
        let offset = slot - b.args.first_instance;
        assert!(offset < b.live_count, "slot outside the live range");
        assert_eq!(
            offset < b.visible_count,
            visible,
            "shown part holds exactly the shown"
        );
        let c = &mut per_batch[record.batch as usize];
        c.0 += u32::from(visible);
        c.1 += 1;
    }
    for (b, (shown, live)) in batches.iter().zip(per_batch) {
        assert_eq!((b.visible_count, b.live_count), (shown, live));
        assert_eq!(b.args.instance_count, 0);
    }
    // Ranges are disjoint and inside the slots; slots outside any live range are empty.
    let mut owner = vec![None; records.len()];
    for (i, b) in batches.iter().enumerate() {
        for s in b.args.first_instance..b.args.first_instance + b.live_count {
            assert!(owner[s as usize].is_none(), "ranges overlap");
            owner[s as usize] = Some(i as u32);
        }
    }
    for (s, o) in owner.iter().enumerate() {
        match o {
            Some(b) => assert_eq!(records[s].batch, *b),
            None => assert_eq!(records[s], PropInstanceRecord::EMPTY, "slot {s}"),
        }
    }
    let _ = primitives;
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    #[test]
    fn random_sequences_keep_batches_consistent(ops in proptest::collection::vec(op(), 1..120)) {
        let mut registry = PropRegistry::new();
        let primitives: Vec<PrimitiveId> = (0..3)
            .map(|i| registry.add_primitive(PropPrimitiveDesc {
                index_count: 3 * (i + 1),
                first_index: i * 100,
                base_vertex: 0,
                sphere_centre: [0.0; 3],
                sphere_radius: 1.0,
            }))
            .collect();
        let mut model: BTreeMap<PropHandle, (u32, u32, PropPlacement, bool)> = BTreeMap::new();
        let mut dead: Vec<PropHandle> = Vec::new();
        let mut mirror = (Vec::new(), Vec::new());
        for op in ops {
            let live: Vec<PropHandle> = model.keys().copied().collect();
            let pick = |i: u8| (!live.is_empty()).then(|| live[i as usize % live.len()]);
            match op {
                Op::Create { primitive, material, x, visible } => {
                    let p = at(i32::from(x), 0, 0);
                    let h = registry
                        .create(primitives[primitive as usize], u32::from(material), p, visible)
                        .unwrap();
                    prop_assert!(!model.contains_key(&h));
                    model.insert(h, (u32::from(primitive), u32::from(material), p, visible));
                }
                Op::Delete(i) => if let Some(h) = pick(i) {
                    registry.delete(h).unwrap();
                    model.remove(&h);
                    dead.push(h);
                },
                Op::Move(i, x) => if let Some(h) = pick(i) {
                    let p = at(0, i32::from(x), 0);
                    registry.set_placement(h, p).unwrap();
                    model.get_mut(&h).unwrap().2 = p;
                },
                Op::Show(i, v) => if let Some(h) = pick(i) {
                    registry.set_visible(h, v).unwrap();
                    model.get_mut(&h).unwrap().3 = v;
                },
                Op::DeleteStale(i) => if !dead.is_empty() {
                    let h = dead[i as usize % dead.len()];
                    prop_assert_eq!(registry.delete(h), Err(PropRegistryError::StaleHandle { handle: h }));
                    prop_assert!(registry.set_visible(h, true).is_err());
                    prop_assert!(registry.set_placement(h, at(0, 0, 0)).is_err());
                },
            }
            let upload = registry.take_upload();
            check(&registry, &model, &primitives, &mut mirror, &upload);
        }
    }
}

#[test]
fn stale_handles_are_refused_after_their_index_is_reused() {
    let mut r = PropRegistry::new();
    let p = unit_primitive(&mut r, 0);
    let a = r.create(p, 0, at(0, 0, 0), true).unwrap();
    r.delete(a).unwrap();
    let b = r.create(p, 0, at(1, 0, 0), true).unwrap();
    assert_eq!(a.index, b.index);
    assert_ne!(a.generation, b.generation);
    let err = r.delete(a).unwrap_err();
    assert_eq!(err, PropRegistryError::StaleHandle { handle: a });
    assert!(err.to_string().contains("stale"));
    assert!(r.get(b).is_ok());
    assert!(matches!(
        r.create(PrimitiveId(9), 0, at(0, 0, 0), true),
        Err(PropRegistryError::UnknownPrimitive { .. })
    ));
}

#[test]
fn an_edit_uploads_only_the_slots_it_touches() {
    let mut r = PropRegistry::new();
    let p = unit_primitive(&mut r, 0);
    let hs: Vec<PropHandle> = (0..4)
        .map(|i| r.create(p, 0, at(i, 0, 0), true).unwrap())
        .collect();
    assert!(r.take_upload().full);
    r.set_placement(hs[2], at(9, 9, 9)).unwrap();
    let u = r.take_upload();
    assert!(!u.full);
    assert_eq!(u.instances, std::iter::once(2..3).collect::<Vec<_>>());
    assert!(u.batches.is_empty());
    // Hiding the first of four shown swaps it with the last shown: two slots and the batch.
    r.set_visible(hs[0], false).unwrap();
    let u = r.take_upload();
    assert_eq!(u.instances, [0..1, 3..4]);
    assert_eq!(u.batches, std::iter::once(0..1).collect::<Vec<_>>());
    assert_eq!(r.take_upload(), PropUpload::default());
}

fn camera_at(voxel: WorldPos) -> Camera {
    Camera::new(voxel, DVec3::new(0.5, 0.5, 0.5), 0.0, 0.0, 1.0)
}

/// A prop at 2^30 from the origin, seen from a camera at the same offset, is placed, culled
/// and Hi-Z tested exactly as at the origin.
#[test]
fn a_far_prop_culls_like_one_at_the_origin() {
    let far = 1 << 30;
    let build = |offset: i32| {
        let mut r = PropRegistry::new();
        let p = unit_primitive(&mut r, 0);
        for i in 0..40 {
            let local = [
                [0.7, 0.2, 0.0, 0.0],
                [-0.2, 0.7, 0.0, 0.0],
                [0.0, 0.0, 1.5, 0.0],
                [0.25, 0.125, 0.375, 1.0],
            ];
            let anchor = WorldPos::new(
                offset + (i % 7) * 3 - 9,
                offset + (i / 7) - 2,
                offset - 5 - i,
            );
            r.create(p, 0, PropPlacement::new(anchor, local).unwrap(), i % 5 != 0)
                .unwrap();
        }
        let cam = camera_at(WorldPos::new(offset, offset, offset));
        (r, cam)
    };
    let (near_r, near_cam) = build(0);
    let (far_r, far_cam) = build(far);
    let (w, h) = (64, 48);
    // A wall at depth 0.005 (10 blocks at near 0.05) over the left half.
    let depth: Vec<f32> = (0..w * h)
        .map(|p| if p % w < w / 2 { 0.005 } else { 0.0 })
        .collect();
    let levels = pyramid_reference(&depth, w, h).unwrap();
    let hiz = PropHiz {
        levels: &levels,
        width: w,
        height: h,
    };
    let flags = PROP_CULL_FRUSTUM | PROP_CULL_OCCLUSION;
    let run = |r: &PropRegistry, cam: &Camera| {
        let u = PropCullUniforms::new(cam, w, h, r.slot_count(), r.batch_count(), flags);
        let eye = u.eye();
        let spheres: Vec<_> = r
            .instance_records()
            .iter()
            .filter(|rec| rec.batch != NO_BATCH)
            .map(|rec| instance_sphere(rec, &r.batch_records()[rec.batch as usize], &eye))
            .collect();
        let culled =
            cull_props_reference(r.instance_records(), r.batch_records(), &u, Some(hiz)).unwrap();
        (spheres, culled)
    };
    let (near_spheres, near_cull) = run(&near_r, &near_cam);
    let (far_spheres, far_cull) = run(&far_r, &far_cam);
    assert_eq!(near_spheres, far_spheres, "bit for bit");
    assert_eq!(near_cull, far_cull);
    let drawn = near_cull.0[0].len();
    assert!(
        drawn > 0 && drawn < 32,
        "the test culls some and keeps some: {drawn}"
    );
}

#[test]
fn the_cull_keeps_what_is_seen_and_drops_what_is_not() {
    let mut r = PropRegistry::new();
    let p = unit_primitive(&mut r, 0);
    let cam = camera_at(WorldPos::new(0, 0, 0));
    let front = r.create(p, 0, at(0, 0, -10), true).unwrap();
    let behind = r.create(p, 0, at(0, 0, 10), true).unwrap();
    let hidden = r.create(p, 0, at(0, 0, -12), false).unwrap();
    let far_behind_wall = r.create(p, 0, at(0, 0, -40), true).unwrap();
    let (w, h) = (32, 32);
    let u = PropCullUniforms::new(
        &cam,
        w,
        h,
        r.slot_count(),
        r.batch_count(),
        PROP_CULL_FRUSTUM,
    );
    let (lists, drawn) =
        cull_props_reference(r.instance_records(), r.batch_records(), &u, None).unwrap();
    let slot = |h| r.get(h).unwrap().2;
    assert_eq!(lists[0], {
        let mut v = vec![slot(front), slot(far_behind_wall)];
        v.sort();
        v
    });
    assert_eq!(drawn[0].args.instance_count, 2);
    assert!(!lists[0].contains(&slot(behind)) && !lists[0].contains(&slot(hidden)));
    // A wall at 20 blocks (depth 0.0025) hides the one at 40 but not the one at 10.
    let depth = vec![0.0025f32; (w * h) as usize];
    let levels = pyramid_reference(&depth, w, h).unwrap();
    let hiz = PropHiz {
        levels: &levels,
        width: w,
        height: h,
    };
    let u = PropCullUniforms {
        flags: PROP_CULL_FRUSTUM | PROP_CULL_OCCLUSION,
        ..u
    };
    let (lists, _) =
        cull_props_reference(r.instance_records(), r.batch_records(), &u, Some(hiz)).unwrap();
    assert_eq!(lists[0], [slot(front)]);
}

#[test]
fn placements_at_world_keep_only_the_fraction_local() {
    let p = PropPlacement::at_world(DVec3::new(1e9 + 0.25, -3.5, 7.0), IDENTITY).unwrap();
    assert_eq!(p.anchor, WorldPos::new(1_000_000_000, -4, 7));
    assert_eq!(p.local[3], [0.25, 0.5, 0.0, 1.0]);
    assert!(PropPlacement::at_world(DVec3::new(1e12, 0.0, 0.0), IDENTITY).is_err());
    let mut bad = IDENTITY;
    bad[0][0] = f32::NAN;
    assert_eq!(
        PropPlacement::new(WorldPos::new(0, 0, 0), bad),
        Err(PlacementError::NonFinite)
    );
}

#[test]
fn normals_follow_the_inverse_transpose() {
    // Scale x by 2: a 45-degree normal in x-y tilts towards y.
    let local = [[2.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [0.0; 3]];
    let s = std::f32::consts::FRAC_1_SQRT_2;
    let n = local_normal(&local, [s, s, 0.0]);
    let want = [1.0 / 5f32.sqrt(), 2.0 / 5f32.sqrt(), 0.0];
    for i in 0..3 {
        assert!((n[i] - want[i]).abs() < 1e-6, "{n:?}");
    }
    // A mirror in x keeps an outward +x normal pointing out (to -x).
    let mirror = [[-1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [0.0; 3]];
    assert_eq!(local_normal(&mirror, [1.0, 0.0, 0.0]), [-1.0, 0.0, 0.0]);
}
