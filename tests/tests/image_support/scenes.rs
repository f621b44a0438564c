//! Small scenes for the image tests, and rendering them on the GPU and the CPU.

use gpu_backend::render::{Renderer, RendererConfig};
use gpu_backend::{GpuContext, PassTime};
use mesher::{MeshSettings, SurfaceMode};
use render_model::antialias::fxaa;
use render_model::camera::Camera;
use render_model::lighting::Lighting;
use viewer::deferred_reference::render_deferred;
use viewer::gpu_view::upload_world_with;
use viewer::reference_raycast::trace_ray;
use voxel_core::storage::{PaletteChunk, WorldMap};
use voxel_core::{BlockId, ChunkSize, Material, MaterialClass, MaterialPalette, WorldPos};

use super::{Image, PixelSurfaces, Surface};

/// Image width of every test.
pub(crate) const WIDTH: u32 = 128;
/// Image height of every test.
pub(crate) const HEIGHT: u32 = 96;
/// The reference raycaster's range, blocks (far beyond every test scene).
pub(crate) const MAX_DISTANCE: f64 = 4000.0;

/// A world, its palette and a camera that frames it.
pub(crate) struct TestScene {
    /// The voxels.
    pub world: WorldMap<PaletteChunk>,
    /// Their materials.
    pub palette: MaterialPalette,
    /// The camera both renderers use.
    pub camera: Camera,
}

/// A scene of the blocks `fill` gives inside `lo..=hi`, every position shifted by `shift`,
/// framed by `viewer::scene::camera_looking_at`.
pub(crate) fn scene_from_fn(
    palette: MaterialPalette,
    size: ChunkSize,
    lo: [i32; 3],
    hi: [i32; 3],
    shift: i32,
    fill: impl Fn(i32, i32, i32) -> BlockId,
) -> TestScene {
    let mut world = WorldMap::new(size);
    for z in lo[2]..=hi[2] {
        for y in lo[1]..=hi[1] {
            for x in lo[0]..=hi[0] {
                let id = fill(x, y, z);
                if !id.is_air() {
                    let p = WorldPos::new(
                        x.wrapping_add(shift),
                        y.wrapping_add(shift),
                        z.wrapping_add(shift),
                    );
                    world.set_block(p, id);
                }
            }
        }
    }
    let at = |p: [i32; 3]| {
        WorldPos::new(
            p[0].wrapping_add(shift),
            p[1].wrapping_add(shift),
            p[2].wrapping_add(shift),
        )
    };
    let camera = viewer::scene::camera_looking_at(at(lo), at(hi));
    TestScene {
        world,
        palette,
        camera,
    }
}

/// A 6 x 6 x 6 cube crossing chunk borders (16^3 chunks), `shift` blocks from the origin on
/// every axis.
pub(crate) fn cube(shift: i32) -> TestScene {
    let mut palette = MaterialPalette::new();
    let stone = palette.push(Material::opaque(180, 90, 60)).unwrap();
    scene_from_fn(
        palette,
        ChunkSize::S16,
        [-3, -2, -3],
        [2, 3, 2],
        shift,
        |_, _, _| stone,
    )
}

/// A sphere of radius 7 in three colour bands, with an emissive band, on a floor with a pool
/// of glass-clear water: AO where they meet, emission and one transparent layer.
pub(crate) fn sphere() -> TestScene {
    let mut palette = MaterialPalette::new();
    let floor = palette.push(Material::opaque(120, 140, 90)).unwrap();
    let bands = [
        palette.push(Material::opaque(200, 60, 50)).unwrap(),
        palette.push(Material::opaque(230, 210, 80)).unwrap(),
        palette.push(Material::opaque(60, 90, 200)).unwrap(),
    ];
    let mut glow = Material::opaque(255, 160, 40);
    glow.emission = 160;
    let glow = palette.push(glow).unwrap();
    let mut water = Material::opaque(40, 110, 200).with_class(MaterialClass::Transparent);
    water.colour[3] = 140;
    let water = palette.push(water).unwrap();
    scene_from_fn(
        palette,
        ChunkSize::S16,
        [-12, -1, -12],
        [12, 15, 12],
        0,
        move |x, y, z| {
            let (dx, dy, dz) = (x, y - 7, z);
            if dx * dx + dy * dy + dz * dz <= 49 {
                if y == 7 {
                    glow
                } else {
                    bands[(y.max(0) / 5).min(2) as usize]
                }
            } else if y == -1 {
                floor
            } else if y == 0 && x >= 4 && z >= 4 && x <= 10 && z <= 10 {
                water
            } else {
                BlockId::AIR
            }
        },
    )
}

/// Two coloured glass panes in different chunks, one behind the other, in front of a white
/// wall: the blend is right only if the far pane is drawn first.
pub(crate) fn glass_panes() -> TestScene {
    let mut palette = MaterialPalette::new();
    let wall = palette.push(Material::opaque(230, 230, 230)).unwrap();
    let glass = |r, g, b| {
        let mut m = Material::opaque(r, g, b).with_class(MaterialClass::Transparent);
        m.colour[3] = 150;
        m
    };
    let red = palette.push(glass(220, 40, 40)).unwrap();
    let blue = palette.push(glass(40, 60, 220)).unwrap();
    let mut scene = scene_from_fn(
        palette,
        ChunkSize::S16,
        [-8, -6, -36],
        [8, 6, -4],
        0,
        move |x, y, z| {
            let inside = x.abs() <= 6 && y.abs() <= 4;
            match z {
                -36 if x.abs() <= 8 && y.abs() <= 6 => wall,
                -20 if inside && x >= -2 => blue,
                -4 if inside && x <= 2 => red,
                _ => BlockId::AIR,
            }
        },
    );
    scene.camera = Camera {
        voxel: WorldPos::new(0, 1, 8),
        fraction: glam::DVec3::new(0.3, 0.4, 0.5),
        yaw: 0.05,
        pitch: -0.03,
        fov_y: 1.2,
        near: Camera::DEFAULT_NEAR,
    };
    scene
}

/// A smoothable dirt hill on a stone floor, pierced by a stone pillar, seen from high above:
/// in NoCubes mode the hill is the smooth layer and the floor and pillar are greedy quads, so
/// the view crosses every kind of seam between the two (hill on floor, pillar through hill)
/// and chunk borders (16^3 chunks). The floor fills the whole view.
pub(crate) fn smooth_hill() -> TestScene {
    let mut palette = MaterialPalette::new();
    let stone = palette.push(Material::opaque(150, 150, 160)).unwrap();
    let dirt = palette
        .push(Material::opaque(130, 90, 50).with_class(MaterialClass::Smoothable))
        .unwrap();
    let mut scene = scene_from_fn(
        palette,
        ChunkSize::S16,
        [-40, -1, -40],
        [39, 12, 39],
        0,
        move |x, y, z| {
            let pillar = (2..=3).contains(&x) && (-1..=0).contains(&z) && y <= 11;
            if y == -1 || pillar {
                stone
            } else if x * x + (y + 2) * (y + 2) + z * z <= 100 {
                dirt
            } else {
                BlockId::AIR
            }
        },
    );
    scene.camera = Camera {
        voxel: WorldPos::new(0, 45, 5),
        fraction: glam::DVec3::new(0.5, 0.5, 0.5),
        yaw: 0.0,
        pitch: -1.4,
        fov_y: 0.8,
        near: Camera::DEFAULT_NEAR,
    };
    scene
}

/// The terrain of the headless viewer, a 48 x 32 x 48 patch (16^3 chunks).
pub(crate) fn terrain() -> TestScene {
    let scene = viewer::scene::terrain_scene(7, ChunkSize::S16, 3, 2, 3);
    let camera =
        viewer::scene::camera_looking_at(WorldPos::new(-24, 0, -24), WorldPos::new(23, 31, 23));
    TestScene {
        world: scene.world,
        palette: scene.palette,
        camera,
    }
}

/// Renders `scene` from `camera` on the GPU (greedy quads); returns the image and the frame's
/// pass times.
pub(crate) fn gpu_render(
    ctx: &GpuContext,
    scene: &TestScene,
    camera: &Camera,
) -> (Image, Vec<PassTime>) {
    gpu_render_with(ctx, scene, camera, SurfaceMode::Greedy)
}

/// [`gpu_render`] with the chunks meshed in `surface` mode (`NoCubes` puts the smoothable
/// blocks in the smooth layer, drawn by the smooth pipeline).
pub(crate) fn gpu_render_with(
    ctx: &GpuContext,
    scene: &TestScene,
    camera: &Camera,
    surface: SurfaceMode,
) -> (Image, Vec<PassTime>) {
    gpu_render_lit(ctx, scene, camera, surface, &Lighting::default(), true)
}

/// [`gpu_render_with`] under `lighting`, with the antialias pass on or off.
pub(crate) fn gpu_render_lit(
    ctx: &GpuContext,
    scene: &TestScene,
    camera: &Camera,
    surface: SurfaceMode,
    lighting: &Lighting,
    antialias: bool,
) -> (Image, Vec<PassTime>) {
    let size = scene.world.size();
    let config = RendererConfig {
        antialias,
        ..RendererConfig::new(WIDTH, HEIGHT, size)
    };
    let mut renderer = Renderer::new(ctx, &config, &scene.palette).expect("renderer");
    let settings = MeshSettings {
        surface,
        clutter: None,
    };
    upload_world_with(&mut renderer, &scene.world, &scene.palette, &settings).expect("upload");
    let render_cam = *camera;
    renderer.set_camera(&render_cam);
    renderer
        .set_lighting(lighting)
        .expect("the test's lighting renders");
    let times = renderer.render().expect("frame");
    let frame = renderer.read_image().expect("readback");
    let depth = frame
        .depth
        .iter()
        .enumerate()
        .map(|(i, &d)| {
            let (x, y) = (i as u32 % WIDTH, i as u32 / WIDTH);
            render_cam.eye_distance(x, y, WIDTH, HEIGHT, d)
        })
        .collect();
    (
        Image {
            width: WIDTH,
            height: HEIGHT,
            rgba: frame.rgba,
            depth,
            surfaces: None,
        },
        times,
    )
}

/// Renders `scene` with the CPU reference shaded like the GPU.
pub(crate) fn cpu_render(scene: &TestScene, camera: &Camera) -> Image {
    cpu_render_lit(scene, camera, &Lighting::default())
}

/// [`cpu_render`] under `lighting`.
pub(crate) fn cpu_render_lit(scene: &TestScene, camera: &Camera, lighting: &Lighting) -> Image {
    let block_at = |p| scene.world.get_block(p);
    let image = render_deferred(
        &block_at,
        &scene.palette,
        camera,
        lighting,
        WIDTH,
        HEIGHT,
        MAX_DISTANCE,
    );
    // The surfaces each pixel's ray met, from the same rays.
    let surfaces = (0..HEIGHT)
        .flat_map(|py| (0..WIDTH).map(move |px| (px, py)))
        .map(|(px, py)| {
            let dir = camera.ray_direction(px, py, WIDTH, HEIGHT);
            let trace = trace_ray(
                &block_at,
                &scene.palette,
                camera.voxel,
                camera.fraction,
                dir,
                MAX_DISTANCE,
            );
            // The planes of the opaque hit and of each transparent surface in front of it.
            let plane = |voxel: WorldPos, normal: [i32; 3]| {
                let face = viewer::deferred_reference::face_of(normal)?;
                let voxel = [voxel.x, voxel.y, voxel.z];
                let coordinate =
                    voxel[face.normal_axis()].wrapping_add(i32::from(face.is_positive()));
                Some(Surface::Plane(face.index(), coordinate))
            };
            let layers = trace
                .layers
                .map(|l| l.and_then(|l| plane(l.voxel, l.normal)));
            PixelSurfaces {
                opaque: trace.hit.and_then(|h| plane(h.voxel, h.normal)),
                layers,
            }
        })
        .collect();
    Image {
        width: image.width,
        height: image.height,
        // The renderer's default anti-aliasing, as the GPU image has it.
        rgba: fxaa(&image.rgba, image.width, image.height),
        depth: image.depth,
        surfaces: Some(surfaces),
    }
}
