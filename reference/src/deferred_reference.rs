//! The reference raycaster shaded like the GPU renderer: the CPU ground truth of the image
//! tests.
//!
//! Same rays and hits as [`reference_raycast`](crate::reference_raycast) (one ray per pixel
//! centre, DDA through voxels), shaded with the deferred lighting model's CPU twin
//! ([`render_model::lighting`]): sun-shadow and sky-visibility rays by the shared rule
//! ([`render_model::lighting::shadow`]: the same grid around the camera's block, the same
//! march and bias, from the hit point) when [`Lighting::shadows`] switches them on,
//! per-vertex ambient occlusion
//! interpolated over each face exactly as the GPU interpolates it over a quad (the mesher's AO
//! rule per corner, the same diagonal flip, linear interpolation over the triangle the hit point
//! lies in), the same materials (specular lobe, metalness: `lighting::surface`), transparent
//! surfaces by the same layer rule (depth tint of volumes, Fresnel) composited back to front,
//! the same sky
//! and distance haze (the hit's distance along the unit ray, which the GPU recovers from its
//! depth buffer) and the same tonemap.
//!
//! One difference remains by construction: the GPU draws *greedy* quads, which merge faces with
//! equal corner AO, and interpolates AO over the merged quad, while this reference interpolates
//! over each unit face. The two agree wherever a merged quad's AO is uniform or varies only
//! across the merge direction (nearly everywhere); where faces with one non-uniform AO pattern
//! repeat along both axes, the shading differs slightly.

use glam::DVec3;
use render_model::lighting::shadow::{GridClipped, Visibility, surface_visibility};
use render_model::lighting::sky::{apply_haze, sky_background};
use render_model::lighting::surface::{
    SurfaceMaterial, haze_layer, over, shade_surface_visible, transparent_layer,
};
use render_model::lighting::{Lighting, output_rgba8};
use voxel_core::{BlockId, FaceDirection, Material, MaterialPalette, WorldPos};

use crate::reference_raycast::{RenderedImage, render_pixels, trace_ray};
use render_model::Camera;

/// The face direction whose outward normal is `normal`, if any.
pub fn face_of(normal: [i32; 3]) -> Option<FaceDirection> {
    FaceDirection::ALL
        .into_iter()
        .find(|f| f.normal() == normal)
}

/// `(du, dv)` of the 4 corners in the order of `PackedQuadFields::corners`.
fn corner_steps(face: FaceDirection) -> [(i32, i32); 4] {
    let swap = matches!(
        face,
        FaceDirection::PosX | FaceDirection::PosY | FaceDirection::NegZ
    );
    [(0, 0), (1, 0), (1, 1), (0, 1)].map(|(a, b)| if swap { (b, a) } else { (a, b) })
}

fn offset(p: WorldPos, axis: usize, by: i32) -> WorldPos {
    let mut a = [p.x, p.y, p.z];
    a[axis] = a[axis].wrapping_add(by);
    WorldPos::new(a[0], a[1], a[2])
}

/// Per-corner ambient occlusion (`0..=3`, order of `PackedQuadFields::corners`) of the face
/// of `voxel` facing `face`: the mesher's rule on the opaque voxels of the layer in front.
pub fn face_ao(
    block_at: &impl Fn(WorldPos) -> BlockId,
    palette: &MaterialPalette,
    voxel: WorldPos,
    face: FaceDirection,
) -> [u8; 4] {
    let solid = |p: WorldPos| palette.class(block_at(p)).is_ok_and(|c| c.is_opaque());
    let n = face.normal();
    let front = WorldPos::new(
        voxel.x.wrapping_add(n[0]),
        voxel.y.wrapping_add(n[1]),
        voxel.z.wrapping_add(n[2]),
    );
    let (w, h) = (face.width_axis(), face.height_axis());
    corner_steps(face).map(|(du, dv)| {
        let side1 = offset(front, w, 2 * du - 1);
        let side2 = offset(front, h, 2 * dv - 1);
        let corner = offset(side1, h, 2 * dv - 1);
        let (s1, s2, c) = (solid(side1), solid(side2), solid(corner));
        if s1 && s2 {
            0
        } else {
            3 - (u8::from(s1) + u8::from(s2) + u8::from(c))
        }
    })
}

/// AO at `(u, v)` (`0..=1` along the face's width and height axes) of a face with corner AO
/// `ao`, interpolated as the GPU does: split along corners 0-2, or 1-3 when
/// `ao[1] + ao[3] > ao[0] + ao[2]`, then linear over the triangle holding the point.
pub fn interpolate_ao(ao: [u8; 4], face: FaceDirection, u: f64, v: f64) -> f32 {
    // a[du][dv]: the AO at the corner (du, dv).
    let mut a = [[0.0f64; 2]; 2];
    for (i, (du, dv)) in corner_steps(face).into_iter().enumerate() {
        a[du as usize][dv as usize] = f64::from(ao[i]);
    }
    let (u, v) = (u.clamp(0.0, 1.0), v.clamp(0.0, 1.0));
    let flip = u32::from(ao[1]) + u32::from(ao[3]) > u32::from(ao[0]) + u32::from(ao[2]);
    let value = if !flip {
        // Diagonal (0, 0)-(1, 1).
        if u >= v {
            a[0][0] + u * (a[1][0] - a[0][0]) + v * (a[1][1] - a[1][0])
        } else {
            a[0][0] + u * (a[1][1] - a[0][1]) + v * (a[0][1] - a[0][0])
        }
    } else if u + v <= 1.0 {
        // Diagonal (1, 0)-(0, 1), lower triangle.
        a[0][0] + u * (a[1][0] - a[0][0]) + v * (a[0][1] - a[0][0])
    } else {
        a[1][1] + (1.0 - u) * (a[0][1] - a[1][1]) + (1.0 - v) * (a[1][0] - a[1][1])
    };
    value as f32
}

/// The shading rule's material of `block` (white, opaque, fully rough for an unknown id).
fn material(palette: &MaterialPalette, block: BlockId) -> SurfaceMaterial {
    match palette.get(block) {
        Ok(m) => SurfaceMaterial::of(m),
        Err(_) => SurfaceMaterial::of(&Material::opaque(255, 255, 255)),
    }
}

/// The normal and AO (`0..=3`) of the face of `voxel` facing `normal`, at the point
/// `distance` along the ray `direction` from the camera.
fn face_point(
    block_at: &impl Fn(WorldPos) -> BlockId,
    palette: &MaterialPalette,
    camera: &Camera,
    direction: DVec3,
    voxel: WorldPos,
    normal: [i32; 3],
    distance: f64,
) -> ([f32; 3], f32) {
    let n = normal.map(|c| c as f32);
    let Some(face) = face_of(normal) else {
        // The eye is inside a block: no face was crossed; shade unoccluded.
        return (n, 3.0);
    };
    // The hit point relative to the voxel, from small numbers only: the voxel difference is
    // an exact integer (i64), the fraction and the ray step are small.
    let rel = [
        i64::from(camera.voxel.x) - i64::from(voxel.x),
        i64::from(camera.voxel.y) - i64::from(voxel.y),
        i64::from(camera.voxel.z) - i64::from(voxel.z),
    ];
    let p = DVec3::new(rel[0] as f64, rel[1] as f64, rel[2] as f64)
        + camera.fraction
        + direction * distance;
    let p = p.to_array();
    let ao = face_ao(block_at, palette, voxel, face);
    (
        n,
        interpolate_ao(ao, face, p[face.width_axis()], p[face.height_axis()]),
    )
}

/// The sun and sky visibility of the opaque surface point `distance` along the ray
/// `direction` with unit normal `n` (the shadow rule, camera-relative as the GPU marches it);
/// open when the lighting has no shadows.
fn visibility(
    block_at: &impl Fn(WorldPos) -> BlockId,
    palette: &MaterialPalette,
    params: &Lighting,
    camera: &Camera,
    direction: DVec3,
    distance: f64,
    n: [f32; 3],
) -> Visibility {
    if !params.shadows.enabled() {
        return Visibility::OPEN;
    }
    // Camera-relative, as the GPU marches: the camera's fraction plus the ray.
    let origin = (camera.fraction + direction * distance)
        .as_vec3()
        .to_array();
    let solid = |c: [i32; 3]| {
        let at = WorldPos::new(
            camera.voxel.x.wrapping_add(c[0]),
            camera.voxel.y.wrapping_add(c[1]),
            camera.voxel.z.wrapping_add(c[2]),
        );
        palette.class(block_at(at)).is_ok_and(|c| c.is_opaque())
    };
    surface_visibility(
        &GridClipped(solid),
        &params.shadows,
        origin,
        n,
        params.sun_direction,
    )
}

/// Renders `width x height` pixels like the GPU renderer (see the [module docs](self)):
/// sRGB RGBA8 and, per pixel, the distance to the first opaque surface (infinity for sky).
pub fn render_deferred(
    block_at: &(impl Fn(WorldPos) -> BlockId + Sync),
    palette: &MaterialPalette,
    camera: &Camera,
    params: &Lighting,
    width: u32,
    height: u32,
    max_distance: f64,
) -> RenderedImage {
    render_pixels(width, height, |px, py| {
        let dir = camera.ray_direction(px, py, width, height);
        let trace = trace_ray(
            block_at,
            palette,
            camera.voxel,
            camera.fraction,
            dir,
            max_distance,
        );
        let unit = dir.as_vec3().to_array();
        let point = |voxel, normal, distance| {
            face_point(block_at, palette, camera, dir, voxel, normal, distance)
        };
        let mut colour = match &trace.hit {
            Some(hit) => {
                let (n, ao) = point(hit.voxel, hit.normal, hit.distance);
                let m = material(palette, hit.block);
                let seen = visibility(block_at, palette, params, camera, dir, hit.distance, n);
                let lit = shade_surface_visible(
                    params,
                    &m,
                    n,
                    ao,
                    unit,
                    seen.sun_factor(),
                    seen.sky_factor(),
                );
                apply_haze(params, lit, unit, hit.distance as f32)
            }
            None => sky_background(params, unit),
        };
        // Each transparent surface is tinted by the distance to the opaque hit behind it,
        // as the transparent pass measures it from the depth buffer (infinite over the sky),
        // and not shadowed, as the transparent pass shades it.
        let behind = trace.hit.map_or(f32::INFINITY, |h| h.distance as f32);
        for layer in trace.layers.iter().rev().flatten() {
            let (n, ao) = point(layer.voxel, layer.normal, layer.distance);
            let m = material(palette, layer.block);
            let distance = layer.distance as f32;
            let lit = transparent_layer(params, &m, n, ao, unit, behind - distance);
            colour = over(colour, haze_layer(params, lit, unit, distance));
        }
        (
            output_rgba8(colour),
            trace.hit.map_or(f32::INFINITY, |h| h.distance as f32),
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn interpolation_hits_the_corner_values() {
        for face in FaceDirection::ALL {
            for ao in [[3, 2, 1, 0], [0, 3, 3, 3], [3, 3, 0, 3], [1, 1, 2, 2]] {
                for (i, (du, dv)) in corner_steps(face).into_iter().enumerate() {
                    let got = interpolate_ao(ao, face, f64::from(du), f64::from(dv));
                    assert_eq!(got, f32::from(ao[i]), "{face:?} {ao:?} corner {i}");
                }
            }
        }
    }

    #[test]
    fn a_lone_block_is_unoccluded_and_a_floor_corner_is_dark() {
        let mut palette = MaterialPalette::new();
        let stone = palette.push(Material::opaque(100, 100, 100)).unwrap();
        let lone = |p: WorldPos| {
            if p == WorldPos::new(0, 0, 0) {
                stone
            } else {
                BlockId::AIR
            }
        };
        assert_eq!(
            face_ao(&lone, &palette, WorldPos::new(0, 0, 0), FaceDirection::PosY),
            [3; 4]
        );
        // A floor with walls at x = -1 and z = -1 above it: the (0, 0) corner of the top face
        // of (0, 0, 0) touches both.
        let corner = |p: WorldPos| {
            if p.y == 0 || (p.y == 1 && (p.x == -1 || p.z == -1)) {
                stone
            } else {
                BlockId::AIR
            }
        };
        let ao = face_ao(
            &corner,
            &palette,
            WorldPos::new(0, 0, 0),
            FaceDirection::PosY,
        );
        assert_eq!(ao.iter().filter(|&&a| a == 0).count(), 1, "{ao:?}");
        assert_eq!(interpolate_ao(ao, FaceDirection::PosY, 0.0, 0.0), 0.0);
    }
}
