//! Valid `.vox` scenes built by the test writer: transforms, several models, hidden nodes and
//! layers, animations, overlaps, palettes and materials land as MagicaVoxel shows them.

#[path = "support/writer.rs"]
mod writer;

use std::collections::BTreeMap;

use voxel_core::storage::VoxelStorage;
use voxel_core::{ChunkSize, MaterialClass};
use voxel_scene::vox::{VoxMaterialKind, VoxOptions, VoxScene, load_vox_with};
use writer::{VoxWriter, two_model_scene};

fn load_with(bytes: &[u8], include_hidden: bool) -> VoxScene {
    let options = VoxOptions {
        include_hidden,
        ..VoxOptions::new(ChunkSize::S16, 1 << 20)
    };
    load_vox_with(bytes, &options).unwrap_or_else(|e| panic!("valid scene refused: {e}"))
}

fn load(bytes: &[u8]) -> VoxScene {
    load_with(bytes, false)
}

/// Every occupied voxel: world position -> block id.
fn voxels(scene: &VoxScene) -> BTreeMap<[i32; 3], u16> {
    let size = scene.world.size();
    let mut out = BTreeMap::new();
    for (coord, chunk) in scene.world.iter() {
        for (local, id) in chunk.iter() {
            if !id.is_air() {
                let p = coord.world_pos(local, size).unwrap();
                out.insert([p.x, p.y, p.z], id.0);
            }
        }
    }
    assert_eq!(out.len(), scene.voxel_count);
    out
}

/// Where MagicaVoxel puts voxel `v` of a model of `size` under rotation `rows` (each row: the
/// input column and its sign) and translation `t`, in world axes: the voxel's centre relative
/// to the box centre, rotated and translated in floating point, floored, then z-up to y-up.
fn expected(v: [u8; 3], size: [i32; 3], rows: [(usize, f64); 3], t: [i32; 3]) -> [i32; 3] {
    let c: [f64; 3] = std::array::from_fn(|i| f64::from(v[i]) + 0.5 - f64::from(size[i]) / 2.0);
    let p: [i32; 3] =
        std::array::from_fn(|i| (rows[i].1 * c[rows[i].0] + f64::from(t[i])).floor() as i32);
    [p[0], p[2], -1 - p[1]]
}

const IDENTITY: [(usize, f64); 3] = [(0, 1.0), (1, 1.0), (2, 1.0)];

#[test]
fn two_transformed_models_land_where_magicavoxel_puts_them() {
    let scene = load(&two_model_scene().bytes());
    let mut want = BTreeMap::new();
    for (v, id) in [
        ([0, 0, 0], 1),
        ([1, 0, 0], 2),
        ([0, 1, 0], 3),
        ([1, 1, 0], 4),
    ] {
        want.insert(expected(v, [2, 2, 1], IDENTITY, [-3, 0, 0]), id);
    }
    // _r = 17: row 0 takes -y, row 1 takes x, row 2 takes z.
    let rows = [(1, -1.0), (0, 1.0), (2, 1.0)];
    for z in 0..3 {
        want.insert(expected([0, 0, z], [1, 1, 3], rows, [4, 2, 1]), 5);
    }
    assert_eq!(voxels(&scene), want);
    // Written out once by hand, so the helper above is checked too.
    assert!(want.contains_key(&[-4, 0, 0]) && want.contains_key(&[4, 2, -3]));
    assert_eq!(scene.report.models_drawn, 2);
    assert!(
        scene.report.notes().is_empty(),
        "{:?}",
        scene.report.notes()
    );
    let (lo, hi) = scene.bounds.unwrap();
    assert_eq!(
        ([lo.x, lo.y, lo.z], [hi.x, hi.y, hi.z]),
        ([-4, 0, -3], [4, 2, 0])
    );
}

#[test]
fn nested_rotations_compose_from_the_root_down() {
    // A 3 x 2 x 1 model under two rotated transforms: the result is the composed rotation,
    // checked against rotating the model's points by each matrix in turn.
    let voxels_in: Vec<[u8; 4]> = (0..3)
        .flat_map(|x| (0..2).map(move |y| [x, y, 0, 1 + x + 3 * y]))
        .collect();
    let mut w = VoxWriter::new();
    w.model([3, 2, 1], &voxels_in)
        .transform(0, &[], 1, -1, &[])
        .group(1, &[], &[2])
        .transform(2, &[], 3, -1, &[("_r", "17"), ("_t", "10 0 0")])
        .group(3, &[], &[4])
        .transform(4, &[], 5, -1, &[("_r", "40"), ("_t", "0 5 -2")])
        .shape(5, &[], &[0]);
    let scene = load(&w.bytes());
    // _r = 17: rows (-y, x, z); _r = 40 (0b0101000): row 0 takes x, row 1 takes z, row 2
    // takes y, row 1 negated.
    let outer = [(1, -1.0), (0, 1.0), (2, 1.0)];
    let inner = [(0, 1.0), (2, -1.0), (1, 1.0)];
    let got = voxels(&scene);
    assert_eq!(got.len(), 6);
    for v in &voxels_in {
        let c: [f64; 3] =
            std::array::from_fn(|i| f64::from(v[i]) + 0.5 - f64::from([3, 2, 1][i]) / 2.0);
        let mid: [f64; 3] =
            std::array::from_fn(|i| inner[i].1 * c[inner[i].0] + [0.0, 5.0, -2.0][i]);
        let p: [i32; 3] = std::array::from_fn(|i| {
            (outer[i].1 * mid[outer[i].0] + [10.0, 0.0, 0.0][i]).floor() as i32
        });
        let world = [p[0], p[2], -1 - p[1]];
        assert_eq!(got.get(&world), Some(&u16::from(v[3])), "voxel {v:?}");
    }
}

/// A scene with a visible model (index 1), a hidden node (index 2) and a model on a hidden
/// layer (index 3).
fn hidden_scene() -> VoxWriter {
    let mut w = VoxWriter::new();
    w.model([1, 1, 1], &[[0, 0, 0, 1]])
        .model([2, 1, 1], &[[0, 0, 0, 2], [1, 0, 0, 2]])
        .model([1, 1, 3], &[[0, 0, 0, 3], [0, 0, 1, 3], [0, 0, 2, 3]])
        .transform(0, &[], 1, -1, &[])
        .group(1, &[], &[2, 4, 6])
        .transform(2, &[], 3, 0, &[("_t", "0 0 0")])
        .shape(3, &[], &[0])
        .transform(4, &[("_hidden", "1")], 5, 0, &[("_t", "5 0 0")])
        .shape(5, &[], &[1])
        .transform(6, &[("_hidden", "0")], 7, 1, &[("_t", "-5 0 0")])
        .shape(7, &[], &[2])
        .layer(0, &[("_hidden", "0")])
        .layer(1, &[("_name", "off"), ("_hidden", "1")]);
    w
}

#[test]
fn hidden_nodes_and_layers_are_left_out_unless_asked_for() {
    let bytes = hidden_scene().bytes();
    let shown = load(&bytes);
    let ids: Vec<u16> = voxels(&shown).into_values().collect();
    assert_eq!(ids, vec![1]);
    assert_eq!(
        (shown.report.hidden_nodes, shown.report.hidden_by_layer),
        (2, 1)
    );
    assert_eq!(shown.report.models_drawn, 1);
    let notes = shown.report.notes().join("\n");
    assert!(
        notes.contains("2 hidden scene nodes") && notes.contains("--hidden"),
        "{notes}"
    );

    let all = load_with(&bytes, true);
    let mut ids: Vec<u16> = voxels(&all).into_values().collect();
    ids.sort_unstable();
    assert_eq!(ids, vec![1, 2, 2, 3, 3, 3]);
    assert_eq!(all.report.hidden_nodes, 0);
}

#[test]
fn a_hidden_group_hides_everything_below_it() {
    let mut w = VoxWriter::new();
    w.model([1, 1, 1], &[[0, 0, 0, 1]])
        .transform(0, &[], 1, -1, &[])
        .group(1, &[("_hidden", "1")], &[2])
        .transform(2, &[], 3, -1, &[])
        .shape(3, &[], &[0]);
    let scene = load(&w.bytes());
    assert_eq!(scene.voxel_count, 0);
    assert!(scene.bounds.is_none());
    assert_eq!(load_with(&w.bytes(), true).voxel_count, 1);
}

#[test]
fn animations_draw_their_first_frame_and_say_so() {
    // A shape with two keyframe models, and a file of frames without a scene graph.
    let mut w = VoxWriter::new();
    w.model([1, 1, 1], &[[0, 0, 0, 1]])
        .model([2, 2, 2], &[[0, 0, 0, 2], [1, 1, 1, 2]])
        .transform(0, &[], 1, -1, &[])
        .shape(1, &[], &[0, 1]);
    let scene = load(&w.bytes());
    assert_eq!(voxels(&scene).into_values().collect::<Vec<_>>(), vec![1]);
    assert!(scene.report.animated);
    assert!(scene.report.notes().join(" ").contains("first frame"));

    let mut w = VoxWriter::new();
    w.chunk(b"PACK", 2u32.to_le_bytes().to_vec())
        .model([3, 3, 3], &[[2, 1, 0, 7]])
        .model([3, 3, 3], &[[0, 0, 0, 8]]);
    let scene = load(&w.bytes());
    // No scene graph: model 0 with its corner at the origin, y up.
    assert_eq!(voxels(&scene), BTreeMap::from([([2, 0, -2], 7)]));
    assert!(scene.report.animated);
}

#[test]
fn overlapping_models_keep_the_later_voxel_and_count_the_overlap() {
    let mut w = VoxWriter::new();
    w.model([1, 1, 1], &[[0, 0, 0, 1]])
        .model([1, 1, 1], &[[0, 0, 0, 2]])
        .transform(0, &[], 1, -1, &[])
        .group(1, &[], &[2, 4])
        .transform(2, &[], 3, -1, &[])
        .shape(3, &[], &[0])
        .transform(4, &[], 5, -1, &[])
        .shape(5, &[], &[1]);
    let scene = load(&w.bytes());
    assert_eq!(voxels(&scene).into_values().collect::<Vec<_>>(), vec![2]);
    assert_eq!(scene.report.overwritten_voxels, 1);
    assert!(scene.report.notes().join(" ").contains("overlap"));
}

/// MagicaVoxel fills a model's dense grid in file order, so of two voxels at one position the
/// later one is drawn; the note gives the count.
#[test]
fn repeated_voxels_keep_the_later_one_and_are_counted() {
    let mut w = VoxWriter::new();
    w.model(
        [3, 3, 3],
        &[[1, 1, 1, 5], [0, 0, 0, 2], [1, 1, 1, 6], [1, 1, 1, 9]],
    );
    let scene = load(&w.bytes());
    assert_eq!(
        voxels(&scene),
        BTreeMap::from([([0, 0, -1], 2), ([1, 1, -2], 9)]),
        "the last voxel at (1, 1, 1) wins"
    );
    assert_eq!(scene.voxel_count, 2);
    assert_eq!(scene.report.repeated_voxels, 2);
    assert_eq!(scene.report.overwritten_voxels, 0);
    let notes = scene.report.notes().join(" ");
    assert!(
        notes.contains("2 voxels repeat a position") && notes.contains("later one"),
        "{notes}"
    );
}

#[test]
fn unknown_chunks_are_skipped_and_reported() {
    let mut w = VoxWriter::new();
    w.chunk(b"rOBJ", writer::dict(&[("_type", "_bloom")]))
        .model([1, 1, 1], &[[0, 0, 0, 1]]);
    // MagicaVoxel's other renderer settings and notes are skipped without a note.
    for id in [
        b"rCAM", b"rLIT", b"rAIR", b"rLEN", b"rDIS", b"POST", b"NOTE", b"IMAP",
    ] {
        w.chunk(id, vec![0; 8]);
    }
    w.chunk(b"ZZZZ", vec![1, 2, 3]);
    let scene = load(&w.bytes());
    assert_eq!(scene.voxel_count, 1);
    let unknown: Vec<String> = scene
        .report
        .unknown_chunks
        .iter()
        .map(ToString::to_string)
        .collect();
    assert_eq!(
        unknown,
        vec![format!("chunk 'ZZZZ' at byte {}", w.offset_of(11))]
    );
}

#[test]
fn without_rgba_the_default_palette_of_the_format_text_is_used() {
    let mut w = VoxWriter::new();
    w.model([3, 1, 1], &[[0, 0, 0, 1], [1, 0, 0, 2], [2, 0, 0, 255]]);
    let scene = load(&w.bytes());
    // default_palette[1] = 0xffffffff, [2] = 0xffccffff, [255] = 0xff111111 (ABGR).
    assert_eq!(scene.materials[1].colour, [255, 255, 255, 255]);
    assert_eq!(scene.materials[2].colour, [255, 255, 204, 255]);
    assert_eq!(scene.materials[255].colour, [17, 17, 17, 255]);
}

#[test]
fn rgba_entry_i_is_colour_index_i_plus_one() {
    let scene = load(&two_model_scene().bytes());
    for index in 1..=255usize {
        let i = (index - 1) as u8;
        assert_eq!(scene.materials[index].colour, [i, 255 - i, 7, 255]);
        let material = scene
            .palette
            .get(voxel_core::BlockId(index as u16))
            .unwrap();
        assert_eq!(material.colour, [i, 255 - i, 7, 255]);
    }
}

/// Some writers leave out the 256th `RGBA` entry, which no colour index reaches: 255 colours
/// give every index its colour.
#[test]
fn a_palette_of_255_colours_colours_every_index() {
    let mut w = VoxWriter::new();
    let colours: Vec<u8> = (0..255u8).flat_map(|i| [i, 255 - i, 9, 255]).collect();
    w.model([2, 1, 1], &[[0, 0, 0, 1], [1, 0, 0, 255]])
        .chunk(b"RGBA", colours);
    let scene = load(&w.bytes());
    for index in 1..=255usize {
        let i = (index - 1) as u8;
        assert_eq!(scene.materials[index].colour, [i, 255 - i, 9, 255]);
    }
}

#[test]
fn matl_materials_map_to_kinds_and_values() {
    let mut w = VoxWriter::new();
    w.model(
        [5, 1, 1],
        &[
            [0, 0, 0, 1],
            [1, 0, 0, 2],
            [2, 0, 0, 3],
            [3, 0, 0, 4],
            [4, 0, 0, 5],
        ],
    )
    .matl(
        1,
        &[("_type", "_glass"), ("_trans", "0.75"), ("_rough", "0.2")],
    )
    .matl(
        2,
        &[("_type", "_metal"), ("_metal", "0.8"), ("_rough", "0.3")],
    )
    .matl(3, &[("_type", "_emit"), ("_emit", "0.5"), ("_flux", "2")])
    .matl(4, &[("_type", "_diffuse"), ("_rough", "0.1")])
    .matl(5, &[("_type", "_sparkle")]);
    let scene = load(&w.bytes());
    let m = &scene.materials;
    assert_eq!(m[1].kind, VoxMaterialKind::Glass);
    assert_eq!((m[1].transparency, m[1].roughness), (0.75, 0.2));
    assert_eq!(m[2].kind, VoxMaterialKind::Metal);
    assert_eq!((m[2].metalness, m[2].roughness), (0.8, 0.3));
    assert_eq!(m[3].kind, VoxMaterialKind::Emit);
    assert_eq!(m[3].emission, 1.5);
    assert_eq!((m[4].kind, m[4].roughness), (VoxMaterialKind::Diffuse, 1.0));
    assert_eq!(m[5].kind, VoxMaterialKind::Diffuse);
    assert_eq!(
        scene.report.unknown_material_types,
        vec![(5, "_sparkle".to_owned())]
    );
    assert!(scene.report.notes().join(" ").contains("\"_sparkle\""));
    // The renderer's palette: glass is transparent with alpha 1 - transparency, emission
    // saturates at the byte's range.
    let glass = scene.palette.get(voxel_core::BlockId(1)).unwrap();
    assert_eq!(
        (glass.class, glass.colour[3]),
        (MaterialClass::Transparent, 64)
    );
    let lamp = scene.palette.get(voxel_core::BlockId(3)).unwrap();
    assert_eq!((lamp.class, lamp.emission), (MaterialClass::Opaque, 255));
    // Its emission of 1.5 is reported, not saturated silently.
    assert_eq!(scene.report.saturated_emission, vec![3]);
    assert!(
        scene
            .report
            .notes()
            .join(" ")
            .contains("materials [3] emit more")
    );
    // Glass is a thin layer with its roughness; metal keeps metalness and roughness; a
    // diffuse index is fully rough, not metal.
    assert_eq!((glass.volume, glass.roughness), (false, 51));
    let metal = scene.palette.get(voxel_core::BlockId(2)).unwrap();
    assert_eq!(
        (metal.class, metal.metalness, metal.roughness),
        (MaterialClass::Opaque, 204, 77)
    );
    let matte = scene.palette.get(voxel_core::BlockId(4)).unwrap();
    assert_eq!((matte.metalness, matte.roughness), (0, 255));
}

#[test]
fn glass_alpha_and_media_volumes_reach_the_renderer() {
    let mut w = VoxWriter::new();
    w.model([3, 1, 1], &[[0, 0, 0, 1], [1, 0, 0, 2], [2, 0, 0, 3]])
        // `_alpha` without `_trans`: opacity, so transparency 1 - 0.6.
        .matl(1, &[("_type", "_glass"), ("_alpha", "0.6")])
        // `_trans` wins over `_alpha`.
        .matl(
            2,
            &[("_type", "_glass"), ("_trans", "0.5"), ("_alpha", "0.9")],
        )
        .matl(3, &[("_type", "_media"), ("_trans", "0.8")]);
    let scene = load(&w.bytes());
    let m = &scene.materials;
    assert!((m[1].transparency - 0.4).abs() < 1e-6, "{:?}", m[1]);
    assert_eq!(m[2].transparency, 0.5);
    let p = |id| *scene.palette.get(voxel_core::BlockId(id)).unwrap();
    assert_eq!(
        (p(1).class, p(1).colour[3], p(1).volume),
        (MaterialClass::Transparent, 153, false)
    );
    assert_eq!(
        (p(3).class, p(3).colour[3], p(3).volume),
        (MaterialClass::Transparent, 51, true)
    );
}

#[test]
fn matt_materials_of_older_files_map_too() {
    let matt = |id: i32, kind: u32, weight: f32, bits: u32, values: &[f32]| {
        let mut c = id.to_le_bytes().to_vec();
        c.extend(kind.to_le_bytes());
        c.extend(weight.to_le_bytes());
        c.extend(bits.to_le_bytes());
        c.extend(values.iter().flat_map(|v| v.to_le_bytes()));
        c
    };
    let mut w = VoxWriter::new();
    w.model([1, 1, 1], &[[0, 0, 0, 1]])
        // Bits as MagicaVoxel wrote them in the sample deer.vox: a value for bit 7 too.
        .chunk(b"MATT", matt(1, 1, 0.6, 0x8e, &[0.4, 0.5, 0.3, 0.3]))
        .chunk(b"MATT", matt(2, 2, 0.25, 0x02, &[0.05]))
        .chunk(b"MATT", matt(3, 3, 0.5, 0x20, &[1.0]));
    let scene = load(&w.bytes());
    let m = &scene.materials;
    assert_eq!(
        (m[1].kind, m[1].metalness, m[1].roughness),
        (VoxMaterialKind::Metal, 0.6, 0.4)
    );
    assert_eq!(
        (m[2].kind, m[2].transparency, m[2].roughness),
        (VoxMaterialKind::Glass, 0.25, 0.05)
    );
    assert_eq!((m[3].kind, m[3].emission), (VoxMaterialKind::Emit, 1.0));
}
