//! Chunk tables on a real device: only dirty slots are written, in coalesced runs, and the GPU
//! buffer matches the CPU mirror after every flush.

mod common;

use gpu_backend::readback::read_whole;
use gpu_backend::residency::chunk_table::TableEntry;
use gpu_backend::residency::{FarChunkTable, MeshedChunkTable, TableError, TableSlot};
use gpu_backend::test_support::headless_or_skip;
use gpu_backend::{DeviceOptions, GpuContext};
use voxel_core::ChunkCoord;
use voxel_core::formats::{
    ChunkDrawInfo, ChunkDrawInfoFields, ChunkKind, FaceLayerRange, LayerRange, MeshedChunkInfo,
    MeshedChunkInfoFields,
};

const INFO: u64 = size_of::<MeshedChunkInfo>() as u64;

fn meshed(i: i32) -> MeshedChunkInfo {
    MeshedChunkInfo::encode(&MeshedChunkInfoFields {
        chunk: ChunkCoord::new(i, -i, i * 7),
        lod: (i % 16) as u32,
        centre: glam::Vec3::splat(i as f32 + 0.5),
        extent: glam::Vec3::splat(8.0),
        opaque_quads: FaceLayerRange {
            offset: 100 * i as u32,
            counts: [1, 2, 3, 4, 5, i as u32],
        },
        transparent_quads: FaceLayerRange::default(),
        smooth_vertices: LayerRange {
            offset: 7,
            count: i as u32,
        },
        clutter_units: LayerRange::default(),
    })
    .unwrap()
}

/// The GPU copy of the slots below the bound equals the CPU mirror.
fn assert_mirrored(ctx: &GpuContext, table: &MeshedChunkTable) {
    let gpu: Vec<MeshedChunkInfo> = read_whole(&ctx.device, &ctx.queue, table.buffer()).unwrap();
    let bound = table.slot_bound() as usize;
    assert_eq!(&gpu[..bound], table.records());
}

#[test]
fn only_changed_slots_are_written() {
    let Some(ctx) = headless_or_skip(&DeviceOptions::default()) else {
        return;
    };
    let limit = ctx.capabilities.max_storage_buffer_binding_size;
    let mut table = MeshedChunkTable::new(&ctx.device, 64, limit).unwrap();
    let slots: Vec<TableSlot> = (0..10).map(|i| table.insert(meshed(i)).unwrap()).collect();
    assert_eq!(slots, (0..10).map(TableSlot).collect::<Vec<_>>());
    let stats = table.flush(&ctx.queue);
    assert_eq!((stats.bytes, stats.writes, stats.slots), (10 * INFO, 1, 10));
    assert_mirrored(&ctx, &table);

    // Plant a marker in clean slot 9 behind the table's back: a flush that rewrote clean slots
    // would erase it.
    let marker = meshed(99);
    ctx.queue
        .write_buffer(table.buffer(), 9 * INFO, bytemuck::bytes_of(&marker));

    // Slots 3, 4, 5 and 7 change: two runs, four records.
    for i in [4, 3, 5, 7] {
        table.set(TableSlot(i), meshed(50 + i as i32)).unwrap();
    }
    // Setting a slot to the record it already holds writes nothing.
    table.set(TableSlot(0), meshed(0)).unwrap();
    assert_eq!(table.dirty_slots(), 4);
    let stats = table.flush(&ctx.queue);
    assert_eq!((stats.bytes, stats.writes, stats.slots), (4 * INFO, 2, 4));
    let gpu: Vec<MeshedChunkInfo> = read_whole(&ctx.device, &ctx.queue, table.buffer()).unwrap();
    assert_eq!(gpu[9], marker, "a clean slot was rewritten");
    assert_eq!(&gpu[..9], &table.records()[..9]);
    table.set(TableSlot(9), meshed(9)).unwrap();
    table.set(TableSlot(9), marker).unwrap();
    table.set(TableSlot(9), meshed(9)).unwrap();
    assert_eq!(
        table.flush(&ctx.queue).bytes,
        INFO,
        "a slot changed thrice is written once"
    );
    assert_mirrored(&ctx, &table);

    // Removing writes the vacant record; the lowest free slot is reused first.
    assert_eq!(table.remove(TableSlot(6)).unwrap(), meshed(6));
    assert_eq!(table.remove(TableSlot(2)).unwrap(), meshed(2));
    assert_eq!(table.get(TableSlot(2)), None);
    assert_eq!(table.len(), 8);
    let stats = table.flush(&ctx.queue);
    assert_eq!((stats.bytes, stats.writes), (2 * INFO, 2));
    assert_mirrored(&ctx, &table);
    assert_eq!(table.records()[2], MeshedChunkInfo::VACANT);
    assert_eq!(table.insert(meshed(20)).unwrap(), TableSlot(2));
    assert_eq!(table.insert(meshed(21)).unwrap(), TableSlot(6));
    assert_eq!(table.insert(meshed(22)).unwrap(), TableSlot(10));
    assert_eq!(table.slot_bound(), 11);
    let stats = table.flush(&ctx.queue);
    assert_eq!((stats.bytes, stats.writes, stats.slots), (3 * INFO, 3, 3));
    assert_mirrored(&ctx, &table);

    // Nothing changed, nothing written.
    assert_eq!(table.flush(&ctx.queue), Default::default());
}

#[test]
fn table_errors() {
    let Some(ctx) = headless_or_skip(&DeviceOptions::default()) else {
        return;
    };
    let limit = ctx.capabilities.max_storage_buffer_binding_size;
    let mut table = FarChunkTable::new(&ctx.device, 2, limit).unwrap();
    let info = ChunkDrawInfo::encode(&ChunkDrawInfoFields {
        chunk: ChunkCoord::new(1, 2, 3),
        kind: ChunkKind::Sprite,
        draw_count: Some(5),
        gigabuffer_index: Some(40),
    })
    .unwrap();
    let a = table.insert(info).unwrap();
    table.insert(info).unwrap();
    assert_eq!(table.insert(info), Err(TableError::Full { capacity: 2 }));
    table.remove(a).unwrap();
    assert_eq!(table.remove(a), Err(TableError::VacantSlot(a)));
    assert_eq!(table.set(a, info), Err(TableError::VacantSlot(a)));
    assert_eq!(
        table.set(TableSlot(5), info),
        Err(TableError::VacantSlot(TableSlot(5)))
    );
    table.flush(&ctx.queue);
    let gpu: Vec<ChunkDrawInfo> = read_whole(&ctx.device, &ctx.queue, table.buffer()).unwrap();
    assert_eq!(gpu[0], ChunkDrawInfo::VACANT);
    assert_eq!(gpu[1], info);
    // The vacant far record decodes: an empty, non-resident chunk.
    let vacant = ChunkDrawInfo::VACANT.decode().unwrap();
    assert_eq!(
        (vacant.kind, vacant.gigabuffer_index),
        (ChunkKind::Empty, None)
    );
    assert!(MeshedChunkInfo::VACANT.decode().is_ok());

    let e = MeshedChunkTable::new(&ctx.device, 1 << 20, 1 << 20).unwrap_err();
    assert!(matches!(e, TableError::TooLarge { .. }), "{e}");
}
