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
//! decoded from sRGB to linear and sampled **in linear space** with the sampler's wrap modes
//! and filters over the mip levels the GPU uploads ([`render_model::props::mip_chain`]):
//! the level of detail [`mip_lod`] of the uv's analytic derivatives to the next pixel along x
//! and y; magnified (`lod <= 0`) level 0 with `magFilter`, minified the `minFilter` within a
//! level and its mipmap mode between levels (nearest: level `ceil(lod + 1/2) - 1`; linear: the
//! two around `lod`; none: level 0), as Vulkan specifies them; alpha the
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
    mip_chain, mip_lod, relative_point,
};
use voxel_scene::props::{
    AlphaMode, Filter, PropMaterial, PropModel, PropSampler, PropTexture, TextureRef, Wrap,
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

/// A texture's mip levels, level 0 first: `(width, height, rgba)`.
struct Mipped<'t> {
    levels: Vec<(u32, u32, std::borrow::Cow<'t, [u8]>)>,
}

impl<'t> Mipped<'t> {
    /// `texture` with the levels the GPU uploads (level 0 alone if they cannot be made: the
    /// GPU refuses such a texture by name).
    fn of(texture: &'t PropTexture) -> Mipped<'t> {
        let (w, h) = (texture.width, texture.height);
        let mut levels = vec![(w, h, std::borrow::Cow::Borrowed(texture.rgba.as_slice()))];
        if let Ok(chain) = mip_chain(w, h, &texture.rgba) {
            levels.extend(
                chain
                    .into_iter()
                    .map(|l| (l.width, l.height, std::borrow::Cow::Owned(l.rgba))),
            );
        }
        Mipped { levels }
    }
}

/// The texel at `uv` of level `level` of `m`, linear RGB and alpha, by `filter`.
fn sample_level(
    m: &Mipped<'_>,
    level: usize,
    s: &PropSampler,
    filter: Filter,
    uv: [f32; 2],
) -> [f32; 4] {
    let Some((w, h, rgba)) = m.levels.get(level.min(m.levels.len().saturating_sub(1))) else {
        return [1.0; 4];
    };
    let (w, h) = (*w, *h);
    if w == 0 || h == 0 || rgba.len() < 4 * w as usize * h as usize {
        return [1.0; 4];
    }
    let texel = |x: u32, y: u32| -> [f32; 4] {
        let at = (y as usize * w as usize + x as usize) * 4;
        let p = &rgba[at..at + 4];
        [
            srgb_to_linear(p[0]),
            srgb_to_linear(p[1]),
            srgb_to_linear(p[2]),
            f32::from(p[3]) / 255.0,
        ]
    };
    let (u, v) = (uv[0] * w as f32, uv[1] * h as f32);
    if filter == Filter::Nearest {
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

/// The texel at `uv` of `m`, linear RGB and alpha, filtered by the sampler at level of detail
/// `lod` (see the [module docs](self)).
fn sample(m: &Mipped<'_>, tex: &TextureRef, uv: [f32; 2], lod: f32) -> [f32; 4] {
    let s = tex.sampler;
    // Not minified (a NaN lod, from a degenerate triangle, reads as magnified).
    if lod.is_nan() || lod <= 0.0 {
        return sample_level(m, 0, &s, s.mag, uv);
    }
    let top = m.levels.len().saturating_sub(1) as f32;
    match s.mip {
        None => sample_level(m, 0, &s, s.min, uv),
        Some(Filter::Nearest) => {
            let level = ((lod + 0.5).ceil() - 1.0).clamp(0.0, top);
            sample_level(m, level as usize, &s, s.min, uv)
        }
        Some(Filter::Linear) => {
            let lod = lod.min(top);
            let lo = lod.floor();
            let t = lod - lo;
            let a = sample_level(m, lo as usize, &s, s.min, uv);
            if t == 0.0 {
                return a;
            }
            let b = sample_level(m, lo as usize + 1, &s, s.min, uv);
            std::array::from_fn(|i| a[i] + (b[i] - a[i]) * t)
        }
    }
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
        textures: &[Mipped<'_>],
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
            .and_then(|t| textures.get(t.texture).map(|tex| (tex, t)));
        let emissive_texture = material
            .emissive_texture
            .and_then(|t| textures.get(t.texture).map(|tex| (tex, t)));
        // The perspective-correct uv at screen point (x, y), inside the triangle or not.
        let uv_at = |x: f32, y: f32| -> [f32; 2] {
            let b = [
                edge(screen[1], screen[2], x, y) / area,
                edge(screen[2], screen[0], x, y) / area,
                edge(screen[0], screen[1], x, y) / area,
            ];
            let pw: [f32; 3] = std::array::from_fn(|i| b[i] * screen[i][3]);
            let sum = pw[0] + pw[1] + pw[2];
            std::array::from_fn(|i| {
                (pw[0] * v[0].uv[i] + pw[1] * v[1].uv[i] + pw[2] * v[2].uv[i]) / sum
            })
        };
        // The level of detail of a texture at (x, y): the uv's change to the next pixel.
        let lod = |tex: &Mipped<'_>, x: f32, y: f32, uv: [f32; 2]| {
            let (dx, dy) = (uv_at(x + 1.0, y), uv_at(x, y + 1.0));
            let (w, h, _) = &tex.levels[0];
            mip_lod(
                [*w, *h],
                [dx[0] - uv[0], dx[1] - uv[1]],
                [dy[0] - uv[0], dy[1] - uv[1]],
            )
        };
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
                let t =
                    texture.map_or([1.0; 4], |(tex, r)| sample(tex, &r, uv, lod(tex, x, y, uv)));
                let albedo = [f[0] * t[0], f[1] * t[1], f[2] * t[2]];
                let alpha = f[3] * t[3];
                if let AlphaMode::Mask { cutoff } = material.alpha_mode
                    && alpha < cutoff
                {
                    continue;
                }
                let lit = shade(self.lighting, albedo, n, 3.0, 0.0);
                let exposure = self.lighting.exposure_rgb();
                let te = emissive_texture
                    .map_or([1.0; 4], |(tex, r)| sample(tex, &r, uv, lod(tex, x, y, uv)));
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
    let mipped: Vec<Vec<Mipped<'_>>> = props
        .iter()
        .map(|p| p.model.textures.iter().map(Mipped::of).collect())
        .collect();
    for pass in [false, true] {
        for (prop, textures) in props.iter().zip(&mipped) {
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
                                textures,
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
