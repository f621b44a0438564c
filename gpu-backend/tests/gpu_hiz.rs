//! The depth pyramid on a real device (lavapipe in CI) against its CPU twins.
//!
//! - build: a random reversed-Z image (sky, flat runs, noise) is rendered into a
//!   `Depth32Float` texture (a full-screen triangle writing `frag_depth` from a storage buffer:
//!   depth textures cannot be copy destinations) and read back to prove it landed bit for bit;
//!   a visibility buffer holds nearer and farther splats on a third of the pixels; every level
//!   of the GPU pyramid, built with and without the buffer, equals `pyramid_reference` of the
//!   same input exactly, at odd, tiny, 1920 x 1080 and random sizes;
//! - test: `hiz_rect_visible` and its steps, run by `hiz_probe.wgsl` (which includes
//!   `hiz.wgsl`) on thousands of random rectangles (tiny to larger than the screen, inverted,
//!   off screen, infinite) with nearest depths at, just above and just below texel values,
//!   decide exactly as `rect_test_reference`: verdict, level, farthest depth, pixel range
//!   (neighbouring invocations test at different levels, which is how this test caught
//!   lavapipe answering `textureDimensions(t, level)` with one lane's level for all lanes);
//! - errors: every refused input is the named `HizError` and records nothing; level-0 bind
//!   groups are cached per input pair; the timed build is timed.
//!
//! Seeds are fixed (`HIZ_TEST_SEED` overrides) and printed.

mod common;
mod gpu_hiz_support;

use std::sync::OnceLock;

use common::Rng;
use gpu_backend::render::passes::hiz::{DepthPyramid, HizError, TAIL_LEVELS};
use gpu_backend::shaders::{HIZ_PROBE, validate};
use gpu_backend::test_support::headless_or_skip;
use gpu_backend::{DeviceOptions, GpuContext, GpuTimer};
use gpu_hiz_support::{
    Answer, Fill, Query, assert_levels_equal, depth_target, probe, random_depth, random_rect,
    random_visibility, read_depth, unit_depth, visibility_buffer,
};
use render_model::hiz::{
    ScreenError, level_sizes, merge_visibility_reference, pyramid_reference, rect_test_reference,
};

/// `HIZ_TEST_SEED` if set, else `default`; printed.
fn seed(default: u64) -> u64 {
    let seed = match std::env::var("HIZ_TEST_SEED") {
        Ok(text) => text.parse().expect("HIZ_TEST_SEED must be a u64"),
        Err(_) => default,
    };
    println!("hiz test seed {seed} (HIZ_TEST_SEED={seed} repeats it)");
    seed
}

/// One device for the whole binary; `None` when skipped.
fn context() -> Option<&'static GpuContext> {
    static CONTEXT: OnceLock<Option<GpuContext>> = OnceLock::new();
    CONTEXT
        .get_or_init(|| headless_or_skip(&DeviceOptions::default()))
        .as_ref()
}

/// Builds `pyramid` from `depth` (+ `visibility`) and reads every level back.
fn build(
    ctx: &GpuContext,
    pyramid: &DepthPyramid,
    depth: &wgpu::TextureView,
    visibility: Option<&wgpu::Buffer>,
) -> Vec<Vec<f32>> {
    let mut encoder = ctx.device.create_command_encoder(&Default::default());
    pyramid
        .record_build(&mut encoder, depth, visibility)
        .expect("valid inputs");
    ctx.queue.submit([encoder.finish()]);
    pyramid
        .read_levels(&ctx.device, &ctx.queue)
        .expect("levels readback")
}

/// Renders a random image of `width x height` (and a visibility buffer) and checks that the
/// pyramid built with and without the buffer equals the reference.
fn check_size(ctx: &GpuContext, fill: &Fill, rng: &mut Rng, width: u32, height: u32) {
    let what = format!("{width}x{height}");
    let tile = [1, 1, 3, 8][rng.below(4) as usize];
    let values = random_depth(rng, width, height, tile);
    let (texture, view) = depth_target(ctx, width, height);
    fill.run(ctx, &view, width, &values);
    let depth = read_depth(ctx, &texture);
    assert!(
        depth == values,
        "{what}: the depth texture does not hold the rendered values"
    );
    let words = random_visibility(rng, &depth);
    let visibility = visibility_buffer(ctx, &words);
    let pyramid = DepthPyramid::new(&ctx.device, width, height).expect("pyramid");
    assert_eq!(
        pyramid.level_sizes(),
        level_sizes(width, height).unwrap().as_slice()
    );
    // Level 0, one dispatch per level but the last four, one for those (none below level 0
    // on a one-level pyramid).
    let levels = pyramid.levels();
    let expected = if levels == 1 {
        1
    } else {
        2 + (levels - 1).saturating_sub(TAIL_LEVELS as u32)
    };
    assert_eq!(pyramid.build_dispatches(), expected, "{what}");
    if (width, height) == (1920, 1080) {
        assert_eq!(
            (levels, expected),
            (10, 7),
            "the count BENCHMARKS.md states"
        );
    }
    let merged = merge_visibility_reference(&depth, &words).unwrap();
    assert!(
        merged != depth || width * height < 64,
        "{what}: the splats change nothing"
    );
    let with = build(ctx, &pyramid, &view, Some(&visibility));
    let want = pyramid_reference(&merged, width, height).unwrap();
    assert_levels_equal(&with, &want, &format!("{what} with visibility"));
    let without = build(ctx, &pyramid, &view, None);
    let want = pyramid_reference(&depth, width, height).unwrap();
    assert_levels_equal(&without, &want, &format!("{what} without visibility"));
}

#[test]
fn the_pyramid_equals_the_reference_at_many_sizes() {
    let Some(ctx) = context() else {
        return;
    };
    let seed = seed(0x417a_b01d);
    let mut rng = Rng::new(seed);
    let fill = Fill::new(&ctx.device);
    let mut sizes = vec![
        (37, 23),
        (1, 1),
        (2, 1),
        (1, 2),
        (3, 3),
        (5, 1),
        (1, 9),
        (64, 64),
        (129, 65),
        (200, 3),
        (1920, 1080),
    ];
    for _ in 0..4 {
        sizes.push((1 + rng.below(400), 1 + rng.below(400)));
    }
    for (width, height) in sizes {
        check_size(ctx, &fill, &mut rng, width, height);
    }
}

/// `(member, offset)` of the WGSL struct `name` of `module`, and its size.
fn wgsl_layout(module: &naga::Module, name: &str) -> (Vec<(String, u32)>, u32) {
    let ty = module
        .types
        .iter()
        .find(|(_, t)| t.name.as_deref() == Some(name))
        .unwrap_or_else(|| panic!("no struct {name}"))
        .1;
    let naga::TypeInner::Struct { members, span } = &ty.inner else {
        panic!("{name} is not a struct");
    };
    let members = members
        .iter()
        .map(|m| (m.name.clone().unwrap_or_default(), m.offset))
        .collect();
    (members, *span)
}

#[test]
fn the_probe_structs_match_the_wgsl() {
    let module = validate(HIZ_PROBE.name, &HIZ_PROBE.source()).unwrap_or_else(|e| panic!("{e}"));
    let (members, size) = wgsl_layout(&module, "HizQuery");
    assert_eq!(size as usize, size_of::<Query>());
    let offsets: Vec<(&str, u32)> = members.iter().map(|(n, o)| (n.as_str(), *o)).collect();
    assert_eq!(
        offsets,
        [
            ("rect_min", 0),
            ("rect_max", 8),
            ("nearest_depth", 16),
            ("pad0", 20),
            ("pad1", 24),
            ("pad2", 28)
        ]
    );
    assert_eq!(std::mem::offset_of!(Query, nearest_depth), 16);
    let (members, size) = wgsl_layout(&module, "HizAnswer");
    assert_eq!(size as usize, size_of::<Answer>());
    let names: Vec<&str> = members.iter().map(|(n, _)| n.as_str()).collect();
    assert_eq!(
        names,
        [
            "visible",
            "level",
            "farthest_bits",
            "pixels_lo",
            "pixels_hi",
            "pad0",
            "pad1",
            "pad2"
        ]
    );
    let offsets: Vec<u32> = members.iter().map(|m| m.1).collect();
    assert_eq!(offsets, [0, 4, 8, 12, 16, 20, 24, 28]);
}

#[test]
fn the_rect_test_agrees_with_the_reference() {
    let Some(ctx) = context() else {
        return;
    };
    let seed = seed(0x417a_4ec7);
    let mut rng = Rng::new(seed);
    let fill = Fill::new(&ctx.device);
    let (mut occluded, mut visible) = (0u32, 0u32);
    for (width, height) in [(37, 23), (1, 1), (317, 181), (1000, 3), (640, 360)] {
        let what = format!("{width}x{height}");
        let tile = if width * height > 64 { 8 } else { 1 };
        let values = random_depth(&mut rng, width, height, tile);
        let (_texture, view) = depth_target(ctx, width, height);
        fill.run(ctx, &view, width, &values);
        let words = random_visibility(&mut rng, &values);
        let visibility = visibility_buffer(ctx, &words);
        let pyramid = DepthPyramid::new(&ctx.device, width, height).expect("pyramid");
        let levels = build(ctx, &pyramid, &view, Some(&visibility));
        let merged = merge_visibility_reference(&values, &words).unwrap();
        assert_levels_equal(
            &levels,
            &pyramid_reference(&merged, width, height).unwrap(),
            &what,
        );
        let all_texels: Vec<f32> = levels.iter().flatten().copied().collect();
        let queries: Vec<Query> = (0..4000)
            .map(|_| {
                let (rect_min, rect_max) = random_rect(&mut rng, width, height);
                let near = all_texels[rng.below(all_texels.len() as u32) as usize];
                let nearest_depth = match rng.below(5) {
                    0 => unit_depth(&mut rng),
                    1 => near,
                    2 => f32::from_bits(near.to_bits() + 1),
                    3 => f32::from_bits(near.to_bits().saturating_sub(1)),
                    _ => near * 0.75,
                };
                Query {
                    rect_min,
                    rect_max,
                    nearest_depth,
                    pad: [0; 3],
                }
            })
            .collect();
        let answers = probe(ctx, &pyramid, &queries);
        assert_eq!(answers.len(), queries.len());
        for (q, a) in queries.iter().zip(&answers) {
            let t = rect_test_reference(
                &levels,
                width,
                height,
                q.rect_min,
                q.rect_max,
                q.nearest_depth,
            )
            .unwrap();
            let pack = |p: [u32; 2]| p[0] | (p[1] << 16);
            let got = (
                a.visible != 0,
                a.level,
                f32::from_bits(a.farthest_bits),
                a.pixels_lo,
                a.pixels_hi,
            );
            let want = (
                t.visible,
                t.level,
                t.farthest,
                pack(t.pixels[0]),
                pack(t.pixels[1]),
            );
            assert!(
                got == want,
                "seed {seed}, {what}: {q:?}: GPU (visible, level, farthest, lo, hi) {got:?}, \
                 reference {want:?} ({t:?})"
            );
            if t.visible {
                visible += 1;
            } else {
                occluded += 1;
            }
        }
    }
    assert!(
        occluded > 2000 && visible > 2000,
        "seed {seed}: {occluded} occluded, {visible} visible: the test exercises too little"
    );
}

#[test]
fn bad_inputs_are_errors_and_record_nothing() {
    let Some(ctx) = context() else {
        return;
    };
    let device = &ctx.device;
    let max = device.limits().max_texture_dimension_2d;
    assert!(matches!(
        DepthPyramid::new(device, 0, 4),
        Err(HizError::Screen(ScreenError::BadSize { width: 0, .. }))
    ));
    assert!(matches!(
        DepthPyramid::new(device, 4, max + 1),
        Err(HizError::Screen(ScreenError::BadSize { .. }))
    ));
    let (w, h) = (20, 10);
    let pyramid = DepthPyramid::new(device, w, h).expect("pyramid");
    let (_t, good) = depth_target(ctx, w, h);
    let texture = |size: (u32, u32), format, usage| {
        device
            .create_texture(&wgpu::TextureDescriptor {
                label: Some("bad depth"),
                size: wgpu::Extent3d {
                    width: size.0,
                    height: size.1,
                    depth_or_array_layers: 1,
                },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage,
                view_formats: &[],
            })
            .create_view(&Default::default())
    };
    let sampled = wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::RENDER_ATTACHMENT;
    let depth32 = wgpu::TextureFormat::Depth32Float;
    let wrong_format = texture((w, h), wgpu::TextureFormat::R32Float, sampled);
    let wrong_size = texture((w + 1, h), depth32, sampled);
    let not_sampled = texture((w, h), depth32, wgpu::TextureUsages::RENDER_ATTACHMENT);
    let buffer = |size: u64, usage| {
        device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("bad visibility"),
            size,
            usage,
            mapped_at_creation: false,
        })
    };
    let needed = u64::from(w * h) * 8;
    let small = buffer(needed - 8, wgpu::BufferUsages::STORAGE);
    let not_storage = buffer(needed, wgpu::BufferUsages::COPY_DST);
    let mut encoder = device.create_command_encoder(&Default::default());
    let mut record = |depth: &wgpu::TextureView, vis: Option<&wgpu::Buffer>| {
        pyramid.record_build(&mut encoder, depth, vis).unwrap_err()
    };
    assert_eq!(
        record(&wrong_format, None),
        HizError::DepthFormat(wgpu::TextureFormat::R32Float)
    );
    assert_eq!(
        record(&wrong_size, None),
        HizError::DepthSize {
            expected: (w, h),
            found: (w + 1, h)
        }
    );
    assert_eq!(record(&not_sampled, None), HizError::DepthNotSampleable);
    assert_eq!(
        record(&good, Some(&small)),
        HizError::VisibilityTooSmall {
            needed,
            found: needed - 8
        }
    );
    assert_eq!(
        record(&good, Some(&not_storage)),
        HizError::VisibilityNotStorage
    );
    // Nothing was recorded: the encoder finishes and submits without a validation error
    // (wgpu's default error handler would panic).
    ctx.queue.submit([encoder.finish()]);
    device
        .poll(wgpu::PollType::wait_indefinitely())
        .expect("poll");
    assert_eq!(
        pyramid.cached_inputs(),
        0,
        "no bind group for refused inputs"
    );

    // A screen whose visibility buffer would exceed the storage binding limit.
    let limit = device.limits().max_storage_buffer_binding_size;
    let edge = max.min(render_model::hiz::MAX_SCREEN_EDGE);
    let height = (limit / 8 / u64::from(edge) + 1).min(u64::from(edge)) as u32;
    if u64::from(edge) * u64::from(height) * 8 > limit {
        let big = DepthPyramid::new(device, edge, height).expect("big pyramid");
        let mut encoder = device.create_command_encoder(&Default::default());
        assert_eq!(
            big.record_build(&mut encoder, &good, Some(&small)),
            Err(HizError::VisibilityTooLarge {
                needed: u64::from(edge) * u64::from(height) * 8,
                max: limit
            })
        );
    } else {
        println!(
            "not checked: a {edge}x{edge} visibility buffer fits this device's {limit}-byte \
             storage binding, so VisibilityTooLarge cannot occur here"
        );
    }
}

#[test]
fn level0_bind_groups_are_cached_per_input_pair() {
    let Some(ctx) = context() else {
        return;
    };
    let (w, h) = (16, 8);
    let pyramid = DepthPyramid::new(&ctx.device, w, h).expect("pyramid");
    let views: Vec<_> = (0..3).map(|_| depth_target(ctx, w, h)).collect();
    let vis = visibility_buffer(ctx, &vec![0u64; (w * h) as usize]);
    let mut encoder = ctx.device.create_command_encoder(&Default::default());
    let mut record = |view: &wgpu::TextureView, v: Option<&wgpu::Buffer>| {
        pyramid.record_build(&mut encoder, view, v).unwrap();
    };
    record(&views[0].1, None);
    record(&views[0].1, None);
    record(&views[0].1, Some(&vis));
    record(&views[0].1, Some(&vis));
    assert_eq!(pyramid.cached_inputs(), 2);
    record(&views[1].1, None);
    record(&views[2].1, None);
    record(&views[2].1, Some(&vis));
    assert_eq!(pyramid.cached_inputs(), 4, "at most 4 pairs are kept");
    ctx.queue.submit([encoder.finish()]);
    ctx.device
        .poll(wgpu::PollType::wait_indefinitely())
        .expect("poll");
}

#[test]
fn the_timed_build_is_timed() {
    let Some(ctx) = context() else {
        return;
    };
    let (w, h) = (64, 48);
    let pyramid = DepthPyramid::new(&ctx.device, w, h).expect("pyramid");
    let (_t, view) = depth_target(ctx, w, h);
    let mut timer = GpuTimer::new(ctx, 4).expect("timer");
    let mut encoder = ctx.device.create_command_encoder(&Default::default());
    match timer.compute_pass_writes("hiz") {
        Some(writes) => {
            pyramid
                .record_build_timed(&mut encoder, &view, None, Some(writes))
                .unwrap();
            timer.resolve(&mut encoder);
            ctx.queue.submit([encoder.finish()]);
            let times = timer.collect().expect("timer");
            assert!(
                times.iter().any(|t| t.label == "hiz"),
                "no time for the build: {times:?}"
            );
        }
        None => {
            // The CPU timing path times scopes, not passes: time the build as a scope.
            let scope = timer.begin(&mut encoder, "hiz");
            pyramid.record_build(&mut encoder, &view, None).unwrap();
            timer.end(&mut encoder, scope);
            timer.resolve(&mut encoder);
            ctx.queue.submit([encoder.finish()]);
            let times = timer.collect().expect("timer");
            assert!(times.iter().any(|t| t.label == "hiz"), "{times:?}");
        }
    }
}
