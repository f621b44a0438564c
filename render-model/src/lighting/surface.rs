//! Surfaces with a material ([`SurfaceMaterial`]): the Lambertian model of [`shade`](super::shade) plus a
//! specular lobe, and transparent layers (water, glass) tinted with the distance the view ray
//! travels inside them. The WGSL twin is `render_common.wgsl`'s `shade_surface` and
//! `transparent_layer`, operation for operation.
//!
//! ```text
//! gloss   = 1 - roughness                     (roughness 0..=1; a fully rough surface has no lobe)
//! kd      = 1 - metalness * gloss             (the diffuse share a smooth metal gives up)
//! diffuse = shade(albedo * kd, n, ao, emission)
//! F0      = mix(0.04, albedo, metalness)      (per channel; 0.04 for water and glass)
//! F(c)    = F0 + (1 - F0) (1 - c)^5           (Schlick)
//! sky     = gloss * F(n.v) * haze_colour(reflect(dir, n))      (sky reflection, no sun disc)
//! sun     = gloss * D(n.h) * F(v.h) / 4 * max(n.l, 0) * sun * exposure
//! D(c)    = a^2 / (pi ((a^2 - 1) c^2 + 1)^2),  a = max(roughness^2, MIN_GGX_ALPHA)   (GGX)
//! opaque  = diffuse + sky + sun
//! ```
//!
//! The sun's lobe uses the implicit visibility term (`G / (4 n.l n.v)` with
//! `G = n.l n.v`), so its peak falls with roughness twice: through `gloss` and through `D`.
//! With roughness 1 the lobe is zero and the result is exactly [`shade`](super::shade)'s (the code skips
//! the lobe; `kd` is 1), which is what every palette without MagicaVoxel materials draws.
//! A smooth metal loses its diffuse light and reflects the sky and the sun tinted by its
//! colour; a fully rough metal is drawn like a diffuse surface of its colour. The diffuse
//! share `kd` scales a metal's emission too. The reflection is of the sky alone, in the
//! mirror direction (below the horizon, the horizon's colour): no ground or block is
//! reflected, and neither the reflection nor the highlight is shadowed here.
//!
//! **Transparent layers.** A transparent surface of opacity `alpha` (its palette alpha) lets
//! through `T` of what lies behind and adds its own lit colour in proportion `1 - T`:
//!
//! ```text
//! thin pane:  1 - T = alpha
//! volume:     1 - T = 1 - (1 - alpha)^d      d = blocks from the surface to the opaque
//!                                                surface behind it along the view ray
//! f        = gloss * mean(F(n.v))            the share reflected, not transmitted
//! colour   = (1 - f) (1 - T) lit + sky + sun   (premultiplied)
//! coverage = (1 - T) + f T
//! out      = colour + behind * (1 - coverage)
//! ```
//!
//! `lit` is the surface's [`shade`](super::shade) colour: a deep volume reads as its material's colour, a
//! shallow one as the floor tinted by it. One block of water seen straight down is tinted
//! exactly as a thin pane of the same alpha, and a rough layer reflects nothing, so without
//! the volume flag and with roughness 1 the layer is plain alpha blending. `d` is measured
//! to the opaque surface behind (the depth buffer's), so a ray that leaves the water through
//! its side into air before it meets the ground counts the air as water too; where nothing
//! opaque is behind, `d` is infinite. The layer is hazed at its own distance
//! ([`haze_layer`]).

use voxel_core::Material;

use super::Lighting;
#[cfg(test)]
use super::shade::shade;
use super::shade::shade_visible;
use super::sky::{haze_colour, haze_transmittance};
use super::tonemap::srgb_to_linear;

/// Fresnel reflectance at normal incidence of water and glass (and of every dielectric here).
pub const DIELECTRIC_F0: f32 = 0.04;

/// The least GGX `a` (roughness squared): a mirror's sun highlight is a lobe about a degree
/// wide rather than a point.
pub const MIN_GGX_ALPHA: f32 = 0.02;

/// The largest distance inside a volume, blocks (an infinite one is clamped to it, where its
/// transmittance is 0 for every alpha above about 1e-5).
pub const MAX_INSIDE: f32 = 1.0e6;

/// A block's material as the shading rule reads it (from a [`Material`], as the GPU decodes
/// its `GpuMaterial`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfaceMaterial {
    /// Linear albedo.
    pub albedo: [f32; 3],
    /// Opacity, 0..=1 (the palette alpha).
    pub alpha: f32,
    /// Emission, 0..=1.
    pub emission: f32,
    /// Perceptual roughness, 0 (mirror) ..= 1 (no specular lobe).
    pub roughness: f32,
    /// Metalness, 0..=1.
    pub metalness: f32,
    /// A transparent volume ([`Material::volume`]).
    pub volume: bool,
}

impl SurfaceMaterial {
    /// The rule's view of `m`: bytes over 255, the colour decoded from sRGB.
    pub fn of(m: &Material) -> SurfaceMaterial {
        let [r, g, b, a] = m.colour;
        SurfaceMaterial {
            albedo: [r, g, b].map(srgb_to_linear),
            alpha: f32::from(a) / 255.0,
            emission: f32::from(m.emission) / 255.0,
            roughness: f32::from(m.roughness) / 255.0,
            metalness: f32::from(m.metalness) / 255.0,
            volume: m.volume,
        }
    }
}

/// A transparent layer's contribution: premultiplied `colour` and `coverage`, composited as
/// `colour + behind * (1 - coverage)` ([`over`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Layer {
    /// Premultiplied display-linear colour.
    pub colour: [f32; 3],
    /// The share of what lies behind that the layer hides.
    pub coverage: f32,
}

fn dot(a: [f32; 3], b: [f32; 3]) -> f32 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn schlick(f0: f32, c: f32) -> f32 {
    let x = 1.0 - c;
    let x2 = x * x;
    f0 + (1.0 - f0) * (x2 * x2 * x)
}

/// The specular lobe of a surface point (the sky reflection scaled by the sky visibility
/// `seen_sky`, plus the sun's highlight scaled by the sun visibility `seen_sun`,
/// display-linear) and the mean Fresnel reflectance towards the eye, both before `gloss`.
fn lobe(
    params: &Lighting,
    m: &SurfaceMaterial,
    n: [f32; 3],
    dir: [f32; 3],
    (seen_sun, seen_sky): (f32, f32),
) -> ([f32; 3], f32) {
    let f0: [f32; 3] =
        core::array::from_fn(|i| DIELECTRIC_F0 + (m.albedo[i] - DIELECTRIC_F0) * m.metalness);
    let v = dir.map(|c| -c);
    let n_dot_v = dot(n, v).max(0.0);
    let d_dot_n = dot(dir, n);
    let r: [f32; 3] = core::array::from_fn(|i| dir[i] - 2.0 * d_dot_n * n[i]);
    let sky = haze_colour(params, r);
    let l = params.sun_direction;
    let n_dot_l = dot(n, l).max(0.0);
    let h_raw: [f32; 3] = core::array::from_fn(|i| l[i] + v[i]);
    let h_len = dot(h_raw, h_raw).sqrt().max(1e-6);
    let h = h_raw.map(|c| c / h_len);
    let n_dot_h = dot(n, h).max(0.0);
    let v_dot_h = dot(v, h).max(0.0);
    let a = (m.roughness * m.roughness).max(MIN_GGX_ALPHA);
    let a2 = a * a;
    let k = n_dot_h * n_dot_h * (a2 - 1.0) + 1.0;
    let d = a2 / (core::f32::consts::PI * k * k);
    let exposure = params.exposure_rgb();
    let light: [f32; 3] = core::array::from_fn(|i| {
        let sun = d * schlick(f0[i], v_dot_h) * 0.25 * n_dot_l * params.sun_colour[i];
        schlick(f0[i], n_dot_v) * sky[i] * seen_sky + sun * exposure[i] * seen_sun
    });
    let fresnel =
        (schlick(f0[0], n_dot_v) + schlick(f0[1], n_dot_v) + schlick(f0[2], n_dot_v)) * (1.0 / 3.0);
    (light, fresnel)
}

/// The lit colour of a surface point and its specular share (see the [module docs](self)):
/// `(diffuse, lobe * gloss, gloss * mean Fresnel)`, the sun and sky scaled by the visibility
/// `seen` (`(sun, sky)`, `lighting::shadow`; `(1, 1)` unshadowed).
fn parts(
    params: &Lighting,
    m: &SurfaceMaterial,
    normal: [f32; 3],
    ao: f32,
    dir: [f32; 3],
    seen: (f32, f32),
) -> ([f32; 3], [f32; 3], f32) {
    let gloss = 1.0 - m.roughness;
    let kd = 1.0 - m.metalness * gloss;
    let albedo = m.albedo.map(|c| c * kd);
    let diffuse = shade_visible(params, albedo, normal, ao, m.emission, seen.0, seen.1);
    if gloss <= 0.0 {
        return (diffuse, [0.0; 3], 0.0);
    }
    let (light, fresnel) = lobe(params, m, normal, dir, seen);
    (diffuse, light.map(|c| c * gloss), fresnel * gloss)
}

/// Exposed (display-linear) colour of an opaque surface point of material `m` with unit
/// `normal` and AO `0..=3`, seen along the unit view ray `dir` (eye to point).
pub fn shade_surface(
    params: &Lighting,
    m: &SurfaceMaterial,
    normal: [f32; 3],
    ao: f32,
    dir: [f32; 3],
) -> [f32; 3] {
    shade_surface_visible(params, m, normal, ao, dir, 1.0, 1.0)
}

/// [`shade_surface`] with the sun scaled by `sun` and the sky by `sky` (the shadow rule's
/// visibility, `lighting::shadow::Visibility`): diffuse and specular alike.
pub fn shade_surface_visible(
    params: &Lighting,
    m: &SurfaceMaterial,
    normal: [f32; 3],
    ao: f32,
    dir: [f32; 3],
    sun: f32,
    sky: f32,
) -> [f32; 3] {
    let (diffuse, specular, _) = parts(params, m, normal, ao, dir, (sun, sky));
    core::array::from_fn(|i| diffuse[i] + specular[i])
}

/// The opacity `1 - T` of a layer of `m` over `inside` blocks (thin layers: the alpha).
pub fn layer_opacity(m: &SurfaceMaterial, inside: f32) -> f32 {
    if !m.volume || m.alpha <= 0.0 {
        return m.alpha;
    }
    if m.alpha >= 1.0 {
        return 1.0;
    }
    let d = inside.clamp(0.0, MAX_INSIDE);
    1.0 - (d * (1.0 - m.alpha).log2()).exp2()
}

/// A transparent surface point of `m` (unit `normal`, AO `0..=3`) seen along `dir`, with the
/// opaque surface behind it `inside` blocks further along the ray (infinite for none): the
/// rule of the [module docs](self), before haze.
pub fn transparent_layer(
    params: &Lighting,
    m: &SurfaceMaterial,
    normal: [f32; 3],
    ao: f32,
    dir: [f32; 3],
    inside: f32,
) -> Layer {
    let (lit, specular, f) = parts(params, m, normal, ao, dir, (1.0, 1.0));
    let o = layer_opacity(m, inside);
    let through = (1.0 - f) * o;
    Layer {
        colour: core::array::from_fn(|i| through * lit[i] + specular[i]),
        coverage: o + f * (1.0 - o),
    }
}

/// `layer` seen through the haze from `distance` blocks along `dir`: its colour goes towards
/// the haze's in proportion to its coverage.
pub fn haze_layer(params: &Lighting, layer: Layer, dir: [f32; 3], distance: f32) -> Layer {
    let t = haze_transmittance(params, distance);
    let haze = haze_colour(params, dir);
    Layer {
        colour: core::array::from_fn(|i| {
            let h = haze[i] * layer.coverage;
            h + (layer.colour[i] - h) * t
        }),
        coverage: layer.coverage,
    }
}

/// `layer` composited over `behind`, as the transparent pass's premultiplied blend does it.
pub fn over(behind: [f32; 3], layer: Layer) -> [f32; 3] {
    core::array::from_fn(|i| layer.colour[i] + behind[i] * (1.0 - layer.coverage))
}

#[cfg(test)]
mod tests {
    use super::*;
    use voxel_core::MaterialClass;

    const DOWN: [f32; 3] = [0.0, -1.0, 0.0];
    const UP: [f32; 3] = [0.0, 1.0, 0.0];

    fn water(roughness: u8, volume: bool) -> SurfaceMaterial {
        let mut m = Material::opaque(40, 90, 170).with_class(MaterialClass::Transparent);
        m.colour[3] = 140;
        m.roughness = roughness;
        m.volume = volume;
        SurfaceMaterial::of(&m)
    }

    #[test]
    fn a_rough_dielectric_is_exactly_lambertian() {
        let params = Lighting::default();
        let m = SurfaceMaterial::of(&Material::opaque(200, 120, 30));
        for n in [UP, [1.0, 0.0, 0.0], [0.0, 0.0, -1.0]] {
            let dir = [0.3f32, -0.8, 0.52];
            let got = shade_surface(&params, &m, n, 2.0, dir);
            assert_eq!(got, shade(&params, m.albedo, n, 2.0, 0.0));
        }
    }

    #[test]
    fn a_rough_thin_layer_is_plain_alpha_blending() {
        let params = Lighting::default();
        let m = water(255, false);
        let layer = transparent_layer(&params, &m, UP, 3.0, DOWN, 7.0);
        let lit = shade(&params, m.albedo, UP, 3.0, 0.0);
        assert_eq!(layer.coverage, m.alpha);
        assert_eq!(layer.colour, lit.map(|c| m.alpha * c));
    }

    #[test]
    fn deeper_volumes_hide_more_and_one_block_is_the_alpha() {
        let m = water(255, true);
        assert!((layer_opacity(&m, 1.0) - m.alpha).abs() < 1e-6);
        let (shallow, deep) = (layer_opacity(&m, 1.0), layer_opacity(&m, 6.0));
        assert!(deep > shallow + 0.3, "{shallow} {deep}");
        assert_eq!(layer_opacity(&m, f32::INFINITY), 1.0);
        assert_eq!(layer_opacity(&water(255, false), 6.0), m.alpha);
    }

    #[test]
    fn grazing_views_reflect_more_than_views_straight_down() {
        let params = Lighting::default();
        let m = water(0, false);
        let down = transparent_layer(&params, &m, UP, 3.0, DOWN, 2.0);
        let s = 0.1f32;
        let grazing = [0.0, -s, -(1.0 - s * s).sqrt()];
        let graze = transparent_layer(&params, &m, UP, 3.0, grazing, 2.0);
        assert!(graze.coverage > down.coverage + 0.2, "{down:?} {graze:?}");
    }

    #[test]
    fn the_sun_highlight_falls_with_roughness() {
        let params = Lighting::default();
        let l = params.sun_direction;
        // The mirror direction of the sun about +y: its highlight's peak.
        let dir = [-l[0], l[1], -l[2]].map(|c| -c);
        let peak = |roughness: u8| {
            let m = SurfaceMaterial::of(&Material {
                roughness,
                ..Material::opaque(30, 30, 30)
            });
            shade_surface(&params, &m, UP, 3.0, dir)[1]
        };
        let (mirror, satin, matte) = (peak(10), peak(120), peak(255));
        assert!(mirror > satin && satin > matte, "{mirror} {satin} {matte}");
    }

    #[test]
    fn a_smooth_metal_is_tinted_by_its_colour_and_loses_its_diffuse() {
        let params = Lighting::default();
        let gold = Material {
            roughness: 40,
            metalness: 255,
            ..Material::opaque(252, 204, 48)
        };
        let m = SurfaceMaterial::of(&gold);
        let dir = [0.3f32, -0.6, -0.74];
        let len = dot(dir, dir).sqrt();
        let dir = dir.map(|c| c / len);
        let metal = shade_surface(&params, &m, [0.0, 0.0, 1.0], 3.0, dir);
        assert!(metal[0] > metal[2] * 2.0, "gold reflects gold: {metal:?}");
        let diffuse = shade(&params, m.albedo, [0.0, 0.0, 1.0], 3.0, 0.0);
        let plastic = SurfaceMaterial {
            metalness: 0.0,
            ..m
        };
        let plastic = shade_surface(&params, &plastic, [0.0, 0.0, 1.0], 3.0, dir);
        // The plastic adds an untinted reflection to its diffuse light; the metal's light is
        // all reflection, tinted gold, so it is the more saturated.
        assert!(plastic[0] >= diffuse[0], "{plastic:?} {diffuse:?}");
        assert!(
            metal[0] / metal[2] > plastic[0] / plastic[2],
            "{metal:?} {plastic:?}"
        );
    }
}
