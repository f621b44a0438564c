//! The renderer's API on a real device: uploads appear, frees disappear, bad input is an
//! error naming the problem (never a panic), a frame is timed pass by pass, and smooth quads
//! render the same in each of their three forms.

use glam::{Vec2, Vec3};
use gpu_backend::DeviceOptions;
use gpu_backend::render::{RenderError, Renderer, RendererConfig};
use gpu_backend::residency::ResidencyError;
use gpu_backend::test_support::headless_or_skip;
use render_model::camera::Camera;
use render_model::resident::ChunkMeshData;
use voxel_core::formats::ChunkLayersData;
use voxel_core::formats::{
    BlockVertex, BlockVertexFields, PackedQuad, PackedQuadFields, SmoothQuads, UnormExtent,
    compact_quad_encode,
};
use voxel_core::{
    BlockId, ChunkCoord, ChunkSize, FaceDirection, Material, MaterialPalette, WorldPos,
};

const SIZE: u32 = 32;

fn palette() -> MaterialPalette {
    let mut p = MaterialPalette::new();
    p.push(Material::opaque(200, 50, 50)).unwrap();
    p
}

/// One 16 x 16 quad: the top face of the chunk's bottom layer.
fn floor() -> [PackedQuad; 1] {
    [PackedQuad::encode(&PackedQuadFields {
        position: [0, 0, 0],
        width: 16,
        height: 16,
        face: FaceDirection::PosY,
        ao: [3; 4],
        block: BlockId(1),
    })
    .unwrap()]
}

/// Looking straight down at the floor of chunk (0, 0, 0) from 10 blocks above.
fn camera_above() -> Camera {
    Camera::new(
        WorldPos::new(8, 10, 8),
        glam::DVec3::splat(0.5),
        0.0,
        -1.5,
        1.0,
    )
}

fn centre_depth(renderer: &Renderer) -> f32 {
    let image = renderer.read_image().expect("readback");
    image.depth[(SIZE / 2 * SIZE + SIZE / 2) as usize]
}

#[test]
fn uploads_appear_and_frees_disappear() {
    let Some(ctx) = headless_or_skip(&DeviceOptions::default()) else {
        return;
    };
    let config = RendererConfig::new(SIZE, SIZE, ChunkSize::S16);
    let mut renderer = Renderer::new(&ctx, &config, &palette()).unwrap();
    renderer.set_camera(&camera_above());
    let quads = floor();
    let mut layers = ChunkLayersData::default();
    layers.opaque_quads[FaceDirection::PosY.index() as usize] = &quads;
    let mesh = ChunkMeshData {
        coord: ChunkCoord::new(0, 0, 0),
        lod: 0,
        layers,
    };

    renderer.render().unwrap();
    assert_eq!(centre_depth(&renderer), 0.0, "nothing uploaded: sky");

    let handle = renderer.upload_chunk(&mesh).unwrap();
    let times = renderer.render().unwrap();
    let labels: Vec<&str> = times.iter().map(|t| t.label.as_str()).collect();
    assert_eq!(
        labels,
        [
            "cull",
            "gbuffer",
            "hiz",
            "cull late",
            "gbuffer late",
            "cull transparent",
            "lighting",
            "transparent",
            "tonemap",
            "antialias"
        ]
    );
    let depth = centre_depth(&renderer);
    let distance = renderer
        .camera()
        .eye_distance(SIZE / 2, SIZE / 2, SIZE, SIZE, depth);
    // The eye is at y = 10.5, the floor's top at y = 1, the view almost straight down.
    assert!(
        (9.0..10.0).contains(&distance),
        "floor at {distance} blocks"
    );

    renderer.free_chunk(handle).unwrap();
    renderer.render().unwrap();
    assert_eq!(centre_depth(&renderer), 0.0, "freed: sky again");
    assert!(matches!(
        renderer.free_chunk(handle),
        Err(RenderError::Residency(ResidencyError::UnknownChunk(h))) if h == handle
    ));
    assert_eq!(renderer.chunk_count(), 0);
}

#[test]
fn bad_input_is_an_error() {
    let Some(ctx) = headless_or_skip(&DeviceOptions::default()) else {
        return;
    };
    let zero = RendererConfig::new(0, 16, ChunkSize::S16);
    let err = Renderer::new(&ctx, &zero, &palette()).unwrap_err();
    assert!(
        matches!(err, RenderError::BadSize { width: 0, .. }),
        "{err}"
    );
    assert!(err.to_string().contains("0x16"), "{err}");

    // A table of two chunks: the third upload is refused and leaves no space allocated.
    let mut small = RendererConfig::new(SIZE, SIZE, ChunkSize::S16);
    small.max_chunks = 2;
    let mut renderer = Renderer::new(&ctx, &small, &palette()).unwrap();
    let quads = floor();
    let mut layers = ChunkLayersData::default();
    layers.opaque_quads[FaceDirection::PosY.index() as usize] = &quads;
    for x in 0..2 {
        let mesh = ChunkMeshData {
            coord: ChunkCoord::new(x, 0, 0),
            lod: 0,
            layers,
        };
        renderer.upload_chunk(&mesh).unwrap();
    }
    let used = renderer.gigabuffer().resident();
    let third = ChunkMeshData {
        coord: ChunkCoord::new(2, 0, 0),
        lod: 0,
        layers,
    };
    let err = renderer.upload_chunk(&third).unwrap_err();
    assert!(
        matches!(err, RenderError::Residency(ResidencyError::Table(_))),
        "{err}"
    );
    assert_eq!(
        renderer.gigabuffer().resident(),
        used,
        "the refused chunk's space was freed"
    );
    assert!(matches!(
        renderer.resize(1 << 20, 4),
        Err(RenderError::BadSize { .. })
    ));
    // Still renders.
    renderer.render().unwrap();
}

/// A smooth mesh's vertices and its quads in the three forms: compact records, u16 and u32
/// indices.
struct SmoothFloor {
    vertices: Vec<BlockVertex>,
    compact: Vec<[u16; 3]>,
    narrow: Vec<[u16; 4]>,
    wide: Vec<[u32; 4]>,
}

/// A wavy smooth floor over chunk (0, 0, 0) with 15 x 15 quads (an odd count), its vertices in
/// scan order.
fn wavy_floor() -> SmoothFloor {
    let n = 16u32;
    // The frame the renderer decodes smooth positions in (`SmoothFrame::nocubes`).
    let extent = UnormExtent::padded_lattice(ChunkSize::S16);
    let mut vertices = Vec::new();
    for z in 0..n {
        for x in 0..n {
            let y = 2.0 + 0.8 * ((x as f32) * 0.7).sin() * ((z as f32) * 0.5).cos();
            let fields = BlockVertexFields {
                // Decoded positions are chunk-local + 1 (the NoCubes frame).
                position: Vec3::new(x as f32 + 1.0, y + 1.0, z as f32 + 1.0),
                normal: Vec3::Y,
                uv: Vec2::ZERO,
                block: BlockId(1),
                extra: 0,
            };
            vertices.push(BlockVertex::encode(&fields, extent).expect("in the extent"));
        }
    }
    let mut quads = Vec::new();
    for z in 0..n - 1 {
        for x in 0..n - 1 {
            let i = |dx: u32, dz: u32| x + dx + (z + dz) * n;
            // Counter-clockwise seen from above; every other quad starts at another corner.
            let q = [i(0, 0), i(0, 1), i(1, 1), i(1, 0)];
            let k = ((x + z) % 4) as usize;
            quads.push(std::array::from_fn(|c| q[(c + k) % 4]));
        }
    }
    let compact = quads
        .iter()
        .map(|&q| compact_quad_encode(q).expect("neighbouring rows of 16 vertices fit"))
        .collect();
    let narrow = quads.iter().map(|q| q.map(|i| i as u16)).collect();
    SmoothFloor {
        vertices,
        compact,
        narrow,
        wide: quads,
    }
}

#[test]
fn smooth_quads_render_alike_in_every_form() {
    let Some(ctx) = headless_or_skip(&DeviceOptions::default()) else {
        return;
    };
    let SmoothFloor {
        vertices,
        compact,
        narrow,
        wide,
    } = wavy_floor();
    assert_eq!(
        compact.len() % 2,
        1,
        "an odd count: the compact buffer ends in a pad"
    );
    let mut images = Vec::new();
    for quads in [
        SmoothQuads::Compact(&compact),
        SmoothQuads::U16(&narrow),
        SmoothQuads::U32(&wide),
    ] {
        let config = RendererConfig::new(SIZE, SIZE, ChunkSize::S16);
        let mut renderer = Renderer::new(&ctx, &config, &palette()).unwrap();
        renderer.set_camera(&camera_above());
        let mesh = ChunkMeshData {
            coord: ChunkCoord::new(0, 0, 0),
            lod: 0,
            layers: ChunkLayersData {
                smooth_vertices: &vertices,
                smooth_quads: quads,
                ..Default::default()
            },
        };
        renderer.upload_chunk(&mesh).unwrap();
        assert_eq!(renderer.smooth_quad_count(), quads.len() as u64);
        assert_eq!(
            renderer.gigabuffer().resident().used_bytes(),
            (16 * vertices.len() + 4 * quads.word_len()) as u64,
            "{:?}: the mesher's bytes, padded to whole words",
            quads.form()
        );
        renderer.render().unwrap();
        let image = renderer.read_image().unwrap();
        // The floor fills the view (nothing is sky).
        assert!(image.depth.iter().all(|&d| d > 0.0), "{:?}", quads.form());
        images.push((quads.form(), image));
    }
    let (_, first) = &images[0];
    for (form, image) in &images[1..] {
        assert!(
            image.rgba == first.rgba && image.depth == first.depth,
            "{form:?} renders differently from the compact quads"
        );
    }
}
