//! The smooth benchmark inputs (`benches/smooth.rs`) keep compact quads and cost at most 24
//! bytes per smooth quad, in both sample types and for the NoCubes terrain chunk.

use benches::smooth_inputs::{
    DensityGrid, nocubes_chunk, nocubes_palette, sine_34, sphere_34, terrain_62, to_i8,
};
use mesher::BlockClasses;
use mesher::blocky::BlockyMesh;
use mesher::smooth::{GridShape, NoCubes, SmoothMesh, SmoothQuads, SurfaceNets};
use voxel_core::BlockId;

#[test]
fn benchmark_inputs_are_compact_and_at_most_24_bytes_per_quad() {
    let mut mesher = SurfaceNets::new();
    let mut mesh = SmoothMesh::new();
    let inputs: [(&str, DensityGrid); 3] = [
        ("sphere34", sphere_34()),
        ("sine34", sine_34()),
        ("terrain62", terrain_62()),
    ];
    for (name, grid) in inputs {
        let shape = GridShape::new(grid.dims).expect("a valid grid");
        let q = to_i8(&grid.samples);
        for i8_samples in [false, true] {
            if i8_samples {
                mesher.mesh_i8(&q, shape, BlockId(1), &mut mesh)
            } else {
                mesher.mesh_f32(&grid.samples, shape, BlockId(1), &mut mesh)
            }
            .expect("finite samples");
            assert!(mesh.quad_count() > 1000, "{name}");
            assert!(
                matches!(mesh.quads(), SmoothQuads::Compact(_)),
                "{name} i8 {i8_samples}"
            );
            // 16 B per vertex + 6 B per quad, a few percent more vertices than quads.
            let bytes = mesh.bytes_per_quad();
            assert!(
                bytes <= 24.0,
                "{name} i8 {i8_samples}: {bytes:.2} B per quad"
            );
            assert_eq!(
                mesh.byte_len(),
                16 * mesh.vertices().len() + 6 * mesh.quad_count()
            );
        }
    }
}

#[test]
fn nocubes_terrain_chunk_is_compact_and_at_most_24_bytes_per_smooth_quad() {
    let classes = BlockClasses::from_palette(&nocubes_palette());
    let (mut smooth, mut cubes) = (SmoothMesh::new(), BlockyMesh::new());
    let stats = NoCubes::new()
        .mesh(&nocubes_chunk(), &classes, &mut smooth, &mut cubes)
        .expect("known ids");
    // Both parts are substantial on this chunk: soil hills and stone caves.
    assert!(
        stats.smooth_quads > 5000 && stats.cube_quads > 5000,
        "{stats:?}"
    );
    assert!(matches!(smooth.quads(), SmoothQuads::Compact(_)));
    let bytes = smooth.bytes_per_quad();
    assert!(bytes <= 24.0, "{bytes:.2} B per smooth quad");
    // Cube faces are 8-byte greedy quads, so the whole chunk costs less per quad.
    let all = (smooth.byte_len() + 8 * cubes.opaque.len()) as f64
        / (stats.smooth_quads + stats.cube_quads) as f64;
    assert!(all < bytes, "{all:.2} B per quad");
}
