//! Wavefront OBJ output: an `.obj` with vertex colours (`v x y z r g b`, the common extension,
//! sRGB values 0-1), normals and faces grouped by material, and a `.mtl` beside it with each
//! material's PBR values (`Pr` roughness, `Pm` metallic, `Ke` emission, `d` opacity; the
//! vertex colours carry the colour, so `Kd` is white).

use std::fmt::Write as _;

use crate::geometry::Geometry;
use crate::pbr::linear_to_srgb;

/// The `.obj` and `.mtl` texts of `geometry`; the `.obj` names its material library
/// `mtl_name`.
pub fn write_obj(geometry: &Geometry, mtl_name: &str) -> (String, String) {
    let mut obj = String::new();
    let mut mtl = String::new();
    let _ = writeln!(obj, "# voxmesh {}", env!("CARGO_PKG_VERSION"));
    let _ = writeln!(obj, "mtllib {mtl_name}");
    let _ = writeln!(mtl, "# voxmesh {}", env!("CARGO_PKG_VERSION"));
    for (i, m) in geometry.materials.iter().enumerate() {
        let _ = writeln!(mtl, "\nnewmtl material{i}");
        let _ = writeln!(mtl, "Kd 1 1 1");
        let _ = writeln!(mtl, "d {}", m.alpha);
        let [r, g, b] = m.emissive.map(|c| c * m.emissive_strength);
        let _ = writeln!(mtl, "Ke {r} {g} {b}");
        let _ = writeln!(mtl, "Pr {}", m.roughness);
        let _ = writeln!(mtl, "Pm {}", m.metallic);
    }
    // OBJ indices are 1-based and global over the file.
    let mut base = 1u64;
    for primitive in &geometry.primitives {
        let _ = writeln!(obj, "usemtl material{}", primitive.material);
        for (p, c) in primitive.positions.iter().zip(&primitive.colours) {
            let [r, g, b] = [c[0], c[1], c[2]].map(|v| linear_to_srgb(f32::from(v) / 65535.0));
            let _ = writeln!(obj, "v {} {} {} {r:.4} {g:.4} {b:.4}", p[0], p[1], p[2]);
        }
        for n in &primitive.normals {
            let _ = writeln!(obj, "vn {} {} {}", n[0], n[1], n[2]);
        }
        for t in primitive.indices.chunks_exact(3) {
            let [a, b, c] = [t[0], t[1], t[2]].map(|i| base + u64::from(i));
            let _ = writeln!(obj, "f {a}//{a} {b}//{b} {c}//{c}");
        }
        base += primitive.positions.len() as u64;
    }
    (obj, mtl)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Primitive;
    use crate::pbr::PbrMaterial;
    use voxel_scene::vox::VoxMaterial;

    #[test]
    fn indices_are_one_based_across_primitives() {
        let material = PbrMaterial::of(&VoxMaterial::diffuse([255, 255, 255, 255]));
        let triangle = Primitive {
            material: 0,
            positions: vec![[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
            normals: vec![[0.0, 0.0, 1.0]; 3],
            colours: vec![[65535, 0, 0, 65535]; 3],
            indices: vec![0, 1, 2],
        };
        let geometry = Geometry {
            materials: vec![material, material],
            primitives: vec![
                triangle.clone(),
                Primitive {
                    material: 1,
                    ..triangle
                },
            ],
            quads: 0,
        };
        let (obj, mtl) = write_obj(&geometry, "m.mtl");
        assert!(obj.contains("mtllib m.mtl"));
        assert!(
            obj.contains("f 1//1 2//2 3//3") && obj.contains("f 4//4 5//5 6//6"),
            "{obj}"
        );
        assert!(obj.contains("v 1 0 0 1.0000 0.0000 0.0000"), "{obj}");
        assert_eq!(obj.matches("\nv ").count(), 6);
        assert!(mtl.contains("newmtl material0") && mtl.contains("newmtl material1"));
    }
}
