//! Saved worlds load with identical voxels; truncated, corrupt and newer files are refused by
//! name; a corrupt chunk is reported while the others load.

use std::path::Path;

use proptest::prelude::*;
use voxel_core::{BlockId, ChunkCoord, ChunkSize, WorldPos};
use voxel_world::region::{REGION_HEADER_LEN, region_of};
use voxel_world::{AirBase, ChunkFaultKind, Edit, RegionFormatError, World, WorldError};

const SIZE: ChunkSize = ChunkSize::S8;

fn region_file(dir: &Path) -> std::path::PathBuf {
    // Region (0, 0, 0) holds the box's three chunks.
    let path = dir.join("r.0.0.0.vxr");
    assert!(path.exists());
    path
}

fn saved_world(dir: &Path) -> World<AirBase> {
    let mut w = World::new(AirBase, SIZE, 0).unwrap();
    w.apply(&[
        Edit::Box {
            min: WorldPos::new(0, 0, 0),
            max: WorldPos::new(20, 3, 5),
            id: BlockId(2),
        },
        Edit::Block {
            pos: WorldPos::new(-1, -1, -1),
            id: BlockId(3),
        },
    ])
    .unwrap();
    w.save(dir).unwrap();
    w
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 32, ..ProptestConfig::default() })]

    #[test]
    fn save_then_load_gives_identical_voxels(
        edits in proptest::collection::vec(
            ([-40i32..40, -40..40, -40..40], 0u32..3, 0u16..4), 1..12)
    ) {
        let dir = tempfile::tempdir().unwrap();
        let mut w = World::new(AirBase, SIZE, 0).unwrap();
        for (i, (p, r, id)) in edits.iter().enumerate() {
            let centre = WorldPos::new(p[0], p[1], p[2]);
            w.apply(&[Edit::Sphere { centre, radius: *r, id: BlockId(*id) }]).unwrap();
            // Saves in between: later saves rewrite only the regions they touch.
            if i.is_multiple_of(3) { w.save(dir.path()).unwrap(); }
        }
        w.save(dir.path()).unwrap();
        let (loaded, report) = World::load(AirBase, dir.path(), 0).unwrap();
        prop_assert!(report.faults.is_empty());
        prop_assert_eq!(loaded.edited().collect::<Vec<_>>(), w.edited().collect::<Vec<_>>());
        for c in w.edited() {
            prop_assert!(loaded.chunks().get(c) == w.chunks().get(c), "chunk {:?}", c);
        }
        prop_assert_eq!(loaded.chunks().len(), w.chunks().len());
    }
}

#[test]
fn truncated_files_are_refused_by_name_at_every_length() {
    let dir = tempfile::tempdir().unwrap();
    saved_world(dir.path());
    let path = region_file(dir.path());
    let full = std::fs::read(&path).unwrap();
    for len in 0..full.len() {
        std::fs::write(&path, &full[..len]).unwrap();
        match World::load(AirBase, dir.path(), 0) {
            Err(WorldError::Region { path: p, error }) => {
                assert_eq!(p, path);
                assert!(
                    matches!(error, RegionFormatError::Truncated { .. }),
                    "length {len}: {error}"
                );
                assert!(
                    WorldError::Region { path: p, error }
                        .to_string()
                        .contains("r."),
                    "the message names the file"
                );
            }
            other => panic!("length {len}: {other:?}"),
        }
    }
}

#[test]
fn bad_magic_newer_versions_and_header_corruption_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    saved_world(dir.path());
    let path = region_file(dir.path());
    let full = std::fs::read(&path).unwrap();
    let refuse = |bytes: &[u8]| {
        std::fs::write(&path, bytes).unwrap();
        match World::load(AirBase, dir.path(), 0) {
            Err(WorldError::Region { error, .. }) => error,
            other => panic!("{other:?}"),
        }
    };
    let mut b = full.clone();
    b[0] = b'X';
    assert!(matches!(refuse(&b), RegionFormatError::BadMagic { .. }));
    let mut b = full.clone();
    b[4] = 2;
    assert_eq!(
        refuse(&b),
        RegionFormatError::UnsupportedVersion {
            version: 2,
            supported: 1
        }
    );
    for at in [6, 9, 21, REGION_HEADER_LEN + 5] {
        let mut b = full.clone();
        b[at] ^= 0x10;
        let e = refuse(&b);
        assert!(
            matches!(
                e,
                RegionFormatError::HeaderChecksum { .. } | RegionFormatError::Truncated { .. }
            ),
            "byte {at}: {e}"
        );
    }
    std::fs::write(dir.path().join("world.vxw"), b"VXWD\x02\x00\x08abcd").unwrap();
    assert!(matches!(
        World::load(AirBase, dir.path(), 0),
        Err(WorldError::WorldFile { .. })
    ));
}

#[test]
fn a_corrupt_chunk_is_reported_and_the_others_load() {
    let dir = tempfile::tempdir().unwrap();
    let w = saved_world(dir.path());
    let path = region_file(dir.path());
    let mut b = std::fs::read(&path).unwrap();
    let last = b.len() - 1;
    b[last] ^= 0xff; // inside the last chunk's bytes
    std::fs::write(&path, &b).unwrap();
    let (loaded, report) = World::load(AirBase, dir.path(), 0).unwrap();
    assert_eq!(report.faults.len(), 1, "{:?}", report.faults);
    let (fault_path, fault) = &report.faults[0];
    assert_eq!(fault_path, &path);
    assert!(matches!(fault.kind, ChunkFaultKind::Checksum { .. }));
    let in_file: Vec<ChunkCoord> = w
        .edited()
        .filter(|&c| Some(region_of(c)) == region_of_file(&path))
        .collect();
    assert!(in_file.len() > 1);
    for c in w.edited().filter(|&c| c != fault.coord) {
        assert!(
            loaded.chunks().get(c) == w.chunks().get(c),
            "chunk {c:?} lost"
        );
    }
    assert!(loaded.chunks().get(fault.coord).is_none());
}

fn region_of_file(path: &Path) -> Option<[i32; 3]> {
    let name = path.file_name()?.to_str()?;
    let mut it = name.strip_prefix("r.")?.strip_suffix(".vxr")?.split('.');
    Some([
        it.next()?.parse().ok()?,
        it.next()?.parse().ok()?,
        it.next()?.parse().ok()?,
    ])
}

#[test]
fn leftover_temporary_files_are_never_read() {
    let dir = tempfile::tempdir().unwrap();
    let w = saved_world(dir.path());
    std::fs::write(dir.path().join("r.0.0.0.vxr.tmp"), b"half a write").unwrap();
    let (loaded, report) = World::load(AirBase, dir.path(), 0).unwrap();
    assert_eq!(report.chunks, w.edited().count());
    assert_eq!(loaded.edited().count(), w.edited().count());
}
