//! The smooth benchmark inputs (`benches/smooth.rs`) keep compact quads and cost at most 24
//! bytes per quad, in both sample types.

use benches::smooth_inputs::{DensityGrid, sine_34, sphere_34, terrain_62, to_i8};
use mesher::smooth::{GridShape, SmoothMesh, SmoothQuads, SurfaceNets};
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
