//! The last check before encoding: every number the `.glb` or `.obj` would hold is finite.
//!
//! JSON has no infinity or NaN (`serde_json` writes `null`, which glTF readers and the
//! Khronos validator refuse), and OBJ readers parse `inf` as garbage. The loader refuses the
//! material values that would overflow (see `voxel_scene::vox::materials`), positions are
//! bounded by the i32 world and `--scale`, so this check is the proof rather than the usual
//! path: it names the first non-finite number instead of writing it.

use crate::Error;
use crate::geometry::Geometry;

/// Fails with [`Error::NotFinite`] naming the first number of `geometry` that is not finite.
pub fn check(geometry: &Geometry) -> Result<(), Error> {
    for (i, m) in geometry.materials.iter().enumerate() {
        let named = [
            ("base colour alpha", m.alpha),
            ("metallic factor", m.metallic),
            ("roughness factor", m.roughness),
            ("emissive factor red", m.emissive[0]),
            ("emissive factor green", m.emissive[1]),
            ("emissive factor blue", m.emissive[2]),
            ("emissive strength", m.emissive_strength),
        ];
        for (what, v) in named {
            if !v.is_finite() {
                return Err(Error::NotFinite(format!("material {i}: {what} is {v}")));
            }
        }
    }
    for (p, primitive) in geometry.primitives.iter().enumerate() {
        for (kind, points) in [
            ("position", &primitive.positions),
            ("normal", &primitive.normals),
        ] {
            if let Some((v, point)) = points
                .iter()
                .enumerate()
                .find(|(_, point)| point.iter().any(|c| !c.is_finite()))
            {
                return Err(Error::NotFinite(format!(
                    "primitive {p}: vertex {v} has the {kind} {point:?}"
                )));
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Primitive;
    use crate::pbr::PbrMaterial;

    fn one_triangle() -> Geometry {
        Geometry {
            materials: vec![PbrMaterial {
                alpha: 1.0,
                blend: false,
                metallic: 0.0,
                roughness: 1.0,
                emissive: [0.0; 3],
                emissive_strength: 1.0,
            }],
            primitives: vec![Primitive {
                material: 0,
                positions: vec![[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
                normals: vec![[0.0, 0.0, 1.0]; 3],
                colours: vec![[65535; 4]; 3],
                indices: vec![0, 1, 2],
            }],
            quads: 1,
        }
    }

    #[test]
    fn finite_geometry_passes_and_the_first_bad_number_is_named() {
        let good = one_triangle();
        assert!(check(&good).is_ok());
        let mut bright = one_triangle();
        bright.materials[0].emissive_strength = f32::INFINITY;
        let err = check(&bright).unwrap_err().to_string();
        assert!(
            err.contains("material 0: emissive strength is inf"),
            "{err}"
        );
        let mut far = one_triangle();
        far.primitives[0].positions[2][1] = f32::NAN;
        let err = check(&far).unwrap_err().to_string();
        assert!(
            err.contains("primitive 0: vertex 2 has the position"),
            "{err}"
        );
    }
}
