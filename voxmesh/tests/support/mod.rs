//! Shared by voxmesh's integration tests: running the built binary, reading back what it
//! wrote (the `.glb` with the `gltf` crate, the `.obj` by hand), measuring meshes (signed
//! volume, area) and counting what they should measure from the voxels themselves.

#![allow(dead_code, reason = "each test file uses a different part")]

#[path = "../../../scene/tests/support/samples.rs"]
pub(crate) mod samples;
#[path = "../../../scene/tests/support/writer.rs"]
pub(crate) mod writer;

use std::collections::{HashMap, HashSet};
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use voxel_core::storage::{PaletteChunk, VoxelStorage, WorldMap};
use voxel_core::{MaterialClass, MaterialPalette};

/// Runs the voxmesh binary with `args`.
pub(crate) fn voxmesh(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_voxmesh"))
        .args(args)
        .output()
        .expect("the voxmesh binary runs")
}

/// Runs voxmesh and expects success; returns its stdout and stderr.
pub(crate) fn voxmesh_ok(args: &[&str]) -> (String, String) {
    let out = voxmesh(args);
    let (stdout, stderr) = (text(&out.stdout), text(&out.stderr));
    assert!(
        out.status.success(),
        "voxmesh {args:?} failed ({}):\n{stdout}\n{stderr}",
        out.status
    );
    (stdout, stderr)
}

/// Bytes as text.
pub(crate) fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).into_owned()
}

/// A fresh temporary folder, removed when dropped.
pub(crate) fn temp_dir() -> tempfile::TempDir {
    tempfile::tempdir().expect("a temporary folder")
}

/// A path as `&str` for command lines.
pub(crate) fn s(path: &Path) -> &str {
    path.to_str().expect("temporary paths are UTF-8")
}

/// The triangles of one primitive (or one OBJ material group), as read back.
#[derive(Clone, Debug, Default)]
pub(crate) struct ReadPrimitive {
    /// Alpha-blended material.
    pub blend: bool,
    /// Base colour alpha.
    pub alpha: f32,
    /// Metallic factor.
    pub metallic: f32,
    /// Roughness factor.
    pub roughness: f32,
    /// Emissive factor times strength.
    pub emission: [f32; 3],
    /// Vertex positions.
    pub positions: Vec<[f64; 3]>,
    /// Vertex normals.
    pub normals: Vec<[f32; 3]>,
    /// Vertex colours, linear RGBA.
    pub colours: Vec<[f32; 4]>,
    /// Triangles.
    pub triangles: Vec<[u32; 3]>,
}

/// Reads a `.glb` back with the `gltf` crate (which validates the document on loading).
pub(crate) fn read_glb(path: &Path) -> Vec<ReadPrimitive> {
    let bytes = std::fs::read(path).unwrap_or_else(|e| panic!("read {}: {e}", path.display()));
    let gltf = gltf::Gltf::from_slice(&bytes)
        .unwrap_or_else(|e| panic!("{}: not a valid glTF: {e}", path.display()));
    let blob = gltf.blob.as_deref().expect("a binary chunk");
    let mut out = Vec::new();
    for mesh in gltf.document.meshes() {
        for primitive in mesh.primitives() {
            assert_eq!(primitive.mode(), gltf::mesh::Mode::Triangles);
            let reader = primitive.reader(|_| Some(blob));
            let material = primitive.material();
            let pbr = material.pbr_metallic_roughness();
            let strength = material.emissive_strength().unwrap_or(1.0);
            let indices: Vec<u32> = reader.read_indices().expect("indices").into_u32().collect();
            out.push(ReadPrimitive {
                blend: material.alpha_mode() == gltf::material::AlphaMode::Blend,
                alpha: pbr.base_color_factor()[3],
                metallic: pbr.metallic_factor(),
                roughness: pbr.roughness_factor(),
                emission: material.emissive_factor().map(|c| c * strength),
                positions: reader
                    .read_positions()
                    .expect("positions")
                    .map(|p| p.map(f64::from))
                    .collect(),
                normals: reader.read_normals().expect("normals").collect(),
                colours: reader
                    .read_colors(0)
                    .expect("vertex colours")
                    .into_rgba_f32()
                    .collect(),
                triangles: indices
                    .chunks_exact(3)
                    .map(|t| [t[0], t[1], t[2]])
                    .collect(),
            });
        }
    }
    out
}

/// Reads an `.obj` written by voxmesh back: one group per `usemtl`.
pub(crate) fn read_obj(path: &Path) -> Vec<ReadPrimitive> {
    let text = std::fs::read_to_string(path).expect("the .obj");
    let mut positions: Vec<[f64; 3]> = Vec::new();
    let mut groups: Vec<ReadPrimitive> = Vec::new();
    let mut faces: Vec<Vec<[u32; 3]>> = Vec::new();
    for line in text.lines() {
        let mut words = line.split_whitespace();
        match words.next() {
            Some("v") => {
                let v: Vec<f64> = words.map(|w| w.parse().expect("a number")).collect();
                positions.push([v[0], v[1], v[2]]);
            }
            Some("usemtl") => {
                groups.push(ReadPrimitive::default());
                faces.push(Vec::new());
            }
            Some("f") => {
                let t: Vec<u32> = words
                    .map(|w| w.split("//").next().unwrap().parse::<u32>().unwrap() - 1)
                    .collect();
                faces
                    .last_mut()
                    .expect("faces after usemtl")
                    .push([t[0], t[1], t[2]]);
            }
            _ => {}
        }
    }
    // Global indices: give every group all positions.
    for (group, f) in groups.iter_mut().zip(faces) {
        group.positions = positions.clone();
        group.triangles = f;
    }
    groups
}

/// Signed volume enclosed by the triangles (divergence theorem), in output units cubed.
pub(crate) fn signed_volume(primitives: &[&ReadPrimitive]) -> f64 {
    let mut six_v = 0.0;
    for p in primitives {
        for t in &p.triangles {
            let [a, b, c] = t.map(|i| p.positions[i as usize]);
            six_v += a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
                + a[2] * (b[0] * c[1] - b[1] * c[0]);
        }
    }
    six_v / 6.0
}

/// Total triangle area, in output units squared.
pub(crate) fn area(primitives: &[&ReadPrimitive]) -> f64 {
    let mut twice = 0.0;
    for p in primitives {
        for t in &p.triangles {
            let [a, b, c] = t.map(|i| p.positions[i as usize]);
            let u = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
            let v = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
            let n = [
                u[1] * v[2] - u[2] * v[1],
                u[2] * v[0] - u[0] * v[2],
                u[0] * v[1] - u[1] * v[0],
            ];
            twice += (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
        }
    }
    twice / 2.0
}

/// The voxels of a world, for counting what a mesh of it must measure.
pub(crate) struct Voxels {
    ids: HashMap<[i32; 3], u16>,
    transparent: HashSet<u16>,
}

impl Voxels {
    /// The voxels of `world`; an id is see-through when `palette` says it is transparent.
    pub(crate) fn of(world: &WorldMap<PaletteChunk>, palette: &MaterialPalette) -> Voxels {
        let size = world.size();
        let mut ids = HashMap::new();
        for (coord, chunk) in world.iter() {
            for (local, id) in chunk.iter() {
                if !id.is_air() {
                    let p = coord.world_pos(local, size).expect("in the world");
                    ids.insert([p.x, p.y, p.z], id.0);
                }
            }
        }
        let transparent = palette
            .as_slice()
            .iter()
            .enumerate()
            .filter(|(_, m)| m.class == MaterialClass::Transparent)
            .map(|(i, _)| i as u16)
            .collect();
        Voxels { ids, transparent }
    }

    /// All voxels.
    pub(crate) fn count(&self) -> usize {
        self.ids.len()
    }

    /// Voxels of see-through ids.
    pub(crate) fn transparent_count(&self) -> usize {
        self.ids
            .values()
            .filter(|id| self.transparent.contains(id))
            .count()
    }

    /// Visible faces by the meshers' rule, counted voxel by voxel: an opaque voxel shows a
    /// face where its neighbour is not opaque; a see-through voxel where its neighbour is air
    /// or a different see-through id.
    pub(crate) fn visible_faces(&self) -> usize {
        let mut faces = 0;
        for (p, id) in &self.ids {
            for d in [
                [1, 0, 0],
                [-1, 0, 0],
                [0, 1, 0],
                [0, -1, 0],
                [0, 0, 1],
                [0, 0, -1],
            ] {
                let q = [p[0] + d[0], p[1] + d[1], p[2] + d[2]];
                let shown = match self.ids.get(&q) {
                    None => true,
                    Some(n) => {
                        let n_see_through = self.transparent.contains(n);
                        if self.transparent.contains(id) {
                            n_see_through && n != id
                        } else {
                            n_see_through
                        }
                    }
                };
                faces += usize::from(shown);
            }
        }
        faces
    }
}

/// A `.vox` file written from `w` into `dir` as `name`.
pub(crate) fn write_vox(dir: &Path, name: &str, w: &writer::VoxWriter) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, w.bytes()).expect("write the test .vox");
    path
}

/// A scene of every material kind and a hidden node: opaque blocks (index 1-3), a metal block
/// (4), a lamp (5, emissive), a glass block (6) apart from the rest, and a hidden model
/// (index 7), under rotated and translated transforms.
pub(crate) fn material_scene() -> writer::VoxWriter {
    let mut w = writer::VoxWriter::new();
    let mut block = Vec::new();
    for x in 0..4u8 {
        for y in 0..3u8 {
            for z in 0..5u8 {
                if (x + y + z) % 4 != 3 {
                    block.push([x, y, z, 1 + (x + z) % 5]);
                }
            }
        }
    }
    let glass: Vec<[u8; 4]> = (0..8).map(|i| [i % 2, i / 2 % 2, i / 4, 6]).collect();
    w.model([4, 3, 5], &block)
        .model([2, 2, 2], &glass)
        .model([1, 1, 1], &[[0, 0, 0, 7]])
        .transform(0, &[], 1, -1, &[])
        .group(1, &[], &[2, 4, 6])
        .transform(2, &[], 3, 0, &[("_t", "0 0 0"), ("_r", "17")])
        .shape(3, &[], &[0])
        .transform(4, &[], 5, 0, &[("_t", "10 3 2")])
        .shape(5, &[], &[1])
        .transform(6, &[("_hidden", "1")], 7, 0, &[("_t", "-9 0 0")])
        .shape(7, &[], &[2])
        .layer(0, &[])
        .matl(
            4,
            &[("_type", "_metal"), ("_metal", "0.9"), ("_rough", "0.25")],
        )
        .matl(5, &[("_type", "_emit"), ("_emit", "0.8"), ("_flux", "1.5")])
        .matl(
            6,
            &[("_type", "_glass"), ("_trans", "0.6"), ("_rough", "0.05")],
        );
    let colours = std::array::from_fn(|i| [(i * 37 % 256) as u8, (i * 91 % 256) as u8, 200, 255]);
    w.palette(&colours);
    w
}
