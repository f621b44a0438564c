//! The CPU reference of the glTF prop pass: a [`PropModel`]'s triangles, placed by its
//! instances and a [`PropPlacement`], rasterised for a [`Camera`] into a depth-tested image
//! and shaded with the deferred lighting model's CPU twin. The ground truth of the GPU prop
//! pass's image tests.
//!
//! **Geometry**, as the GPU pass computes it: each instance's record is the placement's
//! anchor with `local = placement.local * instance.matrix` (composed in `f64`, rounded to
//! `f32` once); a vertex goes camera-relative by [`relative_point`] (the rule of
//! [`render_model::props`]: exact at any distance from the origin), then through
//! [`Camera::view_projection`]; normals by [`local_normal`]. Triangles are clipped against the
//! near plane (`clip.w >= near`) in clip space, then rasterised at pixel centres with edge
//! functions (no top-left rule: a pixel centre exactly on an edge two triangles share is
//! drawn by both, at the same depth); depth is reversed-Z `near / w`, interpolated linearly in
//! screen space, and a fragment is kept when nearer (`>`) than what the pixel holds.
//! Attributes are interpolated perspective-correctly.
//!
//! **Faces.** glTF's counter-clockwise fronts; back faces are culled unless the material is
//! double-sided, where they are lit with the normal turned towards the eye.
//!
//! **Colour.** Albedo = base colour factor (linear) * base colour texture, the texture
//! decoded from sRGB to linear and sampled **bilinearly in linear space** (nearest when the
//! sampler's `magFilter` is nearest; no mipmaps), with the sampler's wrap modes; alpha the
//! product of the factor's and the texel's. `MASK` discards below the cutoff; `BLEND`
//! triangles are drawn after every opaque one, in model order, blended over the colour with
//! [`blend`] and depth-tested without writing depth. Lit colour = [`shade`] with full
//! ambient occlusion (3) and no palette emission, plus the emissive colour (factor times
//! strength times the emissive texture, sampled as the base colour is) as the G-buffer holds
//! it ([`encode_emission`] then [`decode_emission`]) times the exposure; the sky is the lighting's sky background in the pixel's
//! direction (no haze); every pixel goes out through
//! [`output_rgba8`].

use glam::DMat4;
use render_model::Camera;
use render_model::lighting::sky::sky_background;
use render_model::lighting::{Lighting, blend, output_rgba8, shade, srgb_to_linear};
use render_model::props::{
    PropEye, PropInstanceRecord, PropPlacement, decode_emission, encode_emission, local_normal,
    relative_point,
};
use voxel_scene::props::{
    AlphaMode, Filter, PropMaterial, PropModel, PropTexture, TextureRef, Wrap,
};

/// One placed model.
#[derive(Clone, Copy, Debug)]
pub struct PlacedProp<'a> {
    /// The model.
    pub model: &'a PropModel,
    /// Where its model space sits in the world.
    pub placement: PropPlacement,
}

/// What the prop reference draws: colour and depth per pixel.
#[derive(Clone, Debug, PartialEq)]
pub struct PropFrame {
    /// Width, pixels.
    pub width: u32,
    /// Height, pixels.
    pub height: u32,
    /// Row-major RGBA8, sRGB-encoded.
    pub rgba: Vec<u8>,
    /// Row-major reversed-Z depth (`near / view z`), 0 where nothing is drawn.
    pub depth: Vec<f32>,
}

/// The record an instance of `prop` uses: the placement's anchor, `placement.local *
/// matrix` composed in `f64`.
pub fn instance_record(placement: &PropPlacement, matrix: &[[f32; 4]; 4]) -> PropInstanceRecord {
    let a = DMat4::from_cols_array_2d(&placement.local.map(|c| c.map(f64::from)));
    let b = DMat4::from_cols_array_2d(&matrix.map(|c| c.map(f64::from)));
    let local = (a * b).as_mat4().to_cols_array_2d();
    PropPlacement {
        anchor: placement.anchor,
        local,
    }
    .record(0)
}

#[derive(Clone, Copy, Debug)]
struct ClipVertex {
    clip: [f32; 4],
    normal: [f32; 3],
    uv: [f32; 2],
}

fn lerp_vertex(a: &ClipVertex, b: &ClipVertex, t: f32) -> ClipVertex {
    let l = |x: f32, y: f32| x + (y - x) * t;
    ClipVertex {
        clip: std::array::from_fn(|i| l(a.clip[i], b.clip[i])),
        normal: std::array::from_fn(|i| l(a.normal[i], b.normal[i])),
        uv: std::array::from_fn(|i| l(a.uv[i], b.uv[i])),
    }
}

/// The polygon of `tri` on the side `clip.w >= near` (Sutherland-Hodgman, one plane).
fn clip_near(tri: [ClipVertex; 3], near: f32) -> Vec<ClipVertex> {
    let mut out = Vec::with_capacity(4);
    for i in 0..3 {
        let (a, b) = (&tri[i], &tri[(i + 1) % 3]);
        let (da, db) = (a.clip[3] - near, b.clip[3] - near);
        if da >= 0.0 {
            out.push(*a);
        }
        if (da >= 0.0) != (db >= 0.0) {
            out.push(lerp_vertex(a, b, da / (da - db)));
        }
    }
    out
}

fn wrap_coord(t: f32, size: u32, mode: Wrap) -> u32 {
    let n = size as i64;
    let i = t.floor() as i64;
    let v = match mode {
        Wrap::Repeat => i.rem_euclid(n),
        Wrap::ClampToEdge => i.clamp(0, n - 1),
        Wrap::MirroredRepeat => {
            let m = i.rem_euclid(2 * n);
            if m < n { m } else { 2 * n - 1 - m }
        }
    };
    v as u32
}

/// The texel at `uv` of `texture`, linear RGB and alpha, filtered by the sampler.
fn sample(texture: &PropTexture, tex: &TextureRef, uv: [f32; 2]) -> [f32; 4] {
    let (w, h) = (texture.width, texture.height);
    if w == 0 || h == 0 {
        return [1.0; 4];
    }
    let texel = |x: u32, y: u32| -> [f32; 4] {
        let at = (y as usize * w as usize + x as usize) * 4;
        let p = &texture.rgba[at..at + 4];
        [
            srgb_to_linear(p[0]),
            srgb_to_linear(p[1]),
            srgb_to_linear(p[2]),
            f32::from(p[3]) / 255.0,
        ]
    };
    let (u, v) = (uv[0] * w as f32, uv[1] * h as f32);
    let s = tex.sampler;
    if s.mag == Filter::Nearest {
        return texel(wrap_coord(u, w, s.wrap_u), wrap_coord(v, h, s.wrap_v));
    }
    let (u, v) = (u - 0.5, v - 0.5);
    let (fu, fv) = (u - u.floor(), v - v.floor());
    let x0 = wrap_coord(u, w, s.wrap_u);
    let x1 = wrap_coord(u + 1.0, w, s.wrap_u);
    let y0 = wrap_coord(v, h, s.wrap_v);
    let y1 = wrap_coord(v + 1.0, h, s.wrap_v);
    let (a, b, c, d) = (texel(x0, y0), texel(x1, y0), texel(x0, y1), texel(x1, y1));
    std::array::from_fn(|i| {
        let top = a[i] + (b[i] - a[i]) * fu;
        let bottom = c[i] + (d[i] - c[i]) * fu;
        top + (bottom - top) * fv
    })
}

struct Target<'l> {
    width: u32,
    height: u32,
    colour: Vec<[f32; 3]>,
    depth: Vec<f32>,
    lighting: &'l Lighting,
    near: f32,
}

impl Target<'_> {
    /// Rasterises one clipped triangle with `material`; `blend_pass` blends without writing
    /// depth.
    fn triangle(
        &mut self,
        v: [ClipVertex; 3],
        model: &PropModel,
        material: &PropMaterial,
        blend_pass: bool,
    ) {
        let (w, h) = (self.width as f32, self.height as f32);
        let screen = v.map(|p| {
            let inv = 1.0 / p.clip[3];
            let ndc = [p.clip[0] * inv, p.clip[1] * inv];
            [
                (ndc[0] * 0.5 + 0.5) * w,
                (0.5 - ndc[1] * 0.5) * h,
                self.near * inv,
                inv,
            ]
        });
        let edge = |a: [f32; 4], b: [f32; 4], x: f32, y: f32| {
            (b[0] - a[0]) * (y - a[1]) - (b[1] - a[1]) * (x - a[0])
        };
        let area = edge(screen[0], screen[1], screen[2][0], screen[2][1]);
        if area == 0.0 || !area.is_finite() {
            return;
        }
        // Screen y points down: a counter-clockwise (front) triangle has negative area here.
        let back = area > 0.0;
        if back && !material.double_sided {
            return;
        }
        let min_x = screen
            .iter()
            .map(|s| s[0])
            .fold(f32::INFINITY, f32::min)
            .floor()
            .max(0.0);
        let max_x = screen
            .iter()
            .map(|s| s[0])
            .fold(f32::NEG_INFINITY, f32::max)
            .ceil()
            .min(w);
        let min_y = screen
            .iter()
            .map(|s| s[1])
            .fold(f32::INFINITY, f32::min)
            .floor()
            .max(0.0);
        let max_y = screen
            .iter()
            .map(|s| s[1])
            .fold(f32::NEG_INFINITY, f32::max)
            .ceil()
            .min(h);
        if !(min_x < max_x && min_y < max_y) {
            return;
        }
        let texture = material
            .base_colour_texture
            .and_then(|t| model.textures.get(t.texture).map(|tex| (tex, t)));
        let emissive_texture = material
            .emissive_texture
            .and_then(|t| model.textures.get(t.texture).map(|tex| (tex, t)));
        for py in min_y as u32..max_y as u32 {
            for px in min_x as u32..max_x as u32 {
                let (x, y) = (px as f32 + 0.5, py as f32 + 0.5);
                let b = [
                    edge(screen[1], screen[2], x, y) / area,
                    edge(screen[2], screen[0], x, y) / area,
                    edge(screen[0], screen[1], x, y) / area,
                ];
                if b.iter().any(|&c| c < 0.0) {
                    continue;
                }
                let depth = b[0] * screen[0][2] + b[1] * screen[1][2] + b[2] * screen[2][2];
                let at = py as usize * self.width as usize + px as usize;
                let nearer = depth > self.depth[at] && depth <= 1.0;
                if !nearer {
                    continue;
                }
                // Perspective-correct weights: b_i / w_i, normalized.
                let pw: [f32; 3] = std::array::from_fn(|i| b[i] * screen[i][3]);
                let sum = pw[0] + pw[1] + pw[2];
                let pw = pw.map(|c| c / sum);
                let uv: [f32; 2] = std::array::from_fn(|i| {
                    pw[0] * v[0].uv[i] + pw[1] * v[1].uv[i] + pw[2] * v[2].uv[i]
                });
                let mut n: [f32; 3] = std::array::from_fn(|i| {
                    pw[0] * v[0].normal[i] + pw[1] * v[1].normal[i] + pw[2] * v[2].normal[i]
                });
                let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
                if len > 0.0 {
                    n = n.map(|c| c / len);
                }
                if back {
                    n = n.map(|c| -c);
                }
                let f = material.base_colour;
                let t = texture.map_or([1.0; 4], |(tex, r)| sample(tex, &r, uv));
                let albedo = [f[0] * t[0], f[1] * t[1], f[2] * t[2]];
                let alpha = f[3] * t[3];
                if let AlphaMode::Mask { cutoff } = material.alpha_mode
                    && alpha < cutoff
                {
                    continue;
                }
                let lit = shade(self.lighting, albedo, n, 3.0, 0.0);
                let exposure = self.lighting.exposure_rgb();
                let te = emissive_texture.map_or([1.0; 4], |(tex, r)| sample(tex, &r, uv));
                let e: [f32; 3] = std::array::from_fn(|i| {
                    material.emissive[i] * material.emissive_strength * te[i]
                });
                let e = decode_emission(encode_emission(e));
                let colour = std::array::from_fn(|i| lit[i] + e[i] * exposure[i]);
                if blend_pass {
                    self.colour[at] = blend(self.colour[at], colour, alpha);
                } else {
                    self.colour[at] = colour;
                    self.depth[at] = depth;
                }
            }
        }
    }
}

/// Renders `props` for `camera` at `width x height` (see the [module docs](self)).
pub fn render_props(
    props: &[PlacedProp<'_>],
    camera: &Camera,
    lighting: &Lighting,
    width: u32,
    height: u32,
) -> PropFrame {
    let pixels = width as usize * height as usize;
    let view_proj = camera.view_projection(width, height);
    let eye = PropEye::of(camera);
    let near = camera.near as f32;
    let mut target = Target {
        width,
        height,
        colour: (0..pixels as u32)
            .map(|i| {
                let dir = camera.ray_direction(i % width, i / width, width, height);
                sky_background(lighting, dir.as_vec3().to_array())
            })
            .collect(),
        depth: vec![0.0; pixels],
        lighting,
        near,
    };
    let project = |p: [f32; 3]| -> [f32; 4] {
        let m = &view_proj;
        std::array::from_fn(|r| ((m[0][r] * p[0] + m[1][r] * p[1]) + m[2][r] * p[2]) + m[3][r])
    };
    for pass in [false, true] {
        for prop in props {
            let model = prop.model;
            for instance in &model.instances {
                let record = instance_record(&prop.placement, &instance.matrix);
                let Some(mesh) = model.meshes.get(instance.mesh) else {
                    continue;
                };
                for prim in &mesh.primitives {
                    let material = model.material_of(prim);
                    let is_blend = material.alpha_mode == AlphaMode::Blend;
                    if is_blend != pass {
                        continue;
                    }
                    let verts: Vec<ClipVertex> = prim
                        .vertices
                        .iter()
                        .map(|v| ClipVertex {
                            clip: project(relative_point(&record, &eye, v.position)),
                            normal: local_normal(&record.local, v.normal),
                            uv: v.uv,
                        })
                        .collect();
                    for tri in prim.indices.chunks_exact(3) {
                        let Some(t) = [tri[0], tri[1], tri[2]]
                            .map(|i| verts.get(i as usize).copied())
                            .into_iter()
                            .collect::<Option<Vec<_>>>()
                        else {
                            continue;
                        };
                        let polygon = clip_near([t[0], t[1], t[2]], near);
                        for k in 1..polygon.len().saturating_sub(1) {
                            target.triangle(
                                [polygon[0], polygon[k], polygon[k + 1]],
                                model,
                                &material,
                                pass,
                            );
                        }
                    }
                }
            }
        }
    }
    let rgba = target
        .colour
        .iter()
        .flat_map(|&c| output_rgba8(c))
        .collect();
    PropFrame {
        width,
        height,
        rgba,
        depth: target.depth,
    }
}
