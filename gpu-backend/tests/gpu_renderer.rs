//! The renderer's API on a real device: uploads appear, frees disappear, bad input is an
//! error naming the problem (never a panic), and a frame is timed pass by pass.

use gpu_backend::DeviceOptions;
use gpu_backend::gigabuffer::ChunkLayersData;
use gpu_backend::render::{ChunkMeshData, RenderCamera, RenderError, Renderer, RendererConfig};
use gpu_backend::test_support::headless_or_skip;
use voxel_core::formats::{PackedQuad, PackedQuadFields};
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
fn camera_above() -> RenderCamera {
    RenderCamera::from_world(
        WorldPos::new(8, 10, 8),
        [0.5; 3],
        ChunkSize::S16,
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
            "cull transparent",
            "gbuffer",
            "lighting",
            "transparent",
            "tonemap"
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
        Err(RenderError::UnknownChunk(h)) if h == handle
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
            layers,
        };
        renderer.upload_chunk(&mesh).unwrap();
    }
    let used = renderer.gigabuffer().resident();
    let third = ChunkMeshData {
        coord: ChunkCoord::new(2, 0, 0),
        layers,
    };
    let err = renderer.upload_chunk(&third).unwrap_err();
    assert!(matches!(err, RenderError::Table(_)), "{err}");
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
