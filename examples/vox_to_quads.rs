//! The mesher alone: a MagicaVoxel `.vox` file to greedy packed quads (8 bytes each), chunk by
//! chunk, without any GPU. Usage: `vox_to_quads MODEL.vox [OUT.bin]`; the output file holds,
//! per chunk, its coordinate (3 x i32), its opaque and transparent quad counts (2 x u32) and
//! those quads, little-endian.

use std::error::Error;
use std::path::PathBuf;

use mesher::BlockClasses;
use mesher::blocky::{BlockyMesh, GreedyMesher};
use voxel_core::storage::gather_neighbourhood;
use voxel_core::{ChunkSize, PaddedChunk};

fn main() -> Result<(), Box<dyn Error>> {
    let mut args = std::env::args_os().skip(1).map(PathBuf::from);
    let input = args
        .next()
        .ok_or("usage: vox_to_quads MODEL.vox [OUT.bin]")?;
    let output = args.next();

    // Load: voxels in 32^3 chunks, block id i = the file's colour index i.
    let scene = voxel_scene::vox::load_vox_file(&input, ChunkSize::S32, 1 << 26)?;
    let classes = BlockClasses::from_palette(&scene.palette);

    // Mesh each stored chunk from its padded neighbourhood (the chunk plus a 1-voxel border
    // read from its neighbours, so faces between chunks are culled correctly).
    let mut coords: Vec<_> = scene.world.iter().map(|(coord, _)| coord).collect();
    coords.sort_unstable();
    let mut padded = PaddedChunk::new(scene.world.size());
    let mut mesher = GreedyMesher::new().with_ambient_occlusion(true);
    let mut mesh = BlockyMesh::new();
    let (mut opaque, mut transparent) = (0usize, 0usize);
    let mut bytes = Vec::new();
    for coord in coords {
        gather_neighbourhood(&scene.world, coord, &mut padded);
        mesher.mesh(&padded, &classes, &mut mesh)?;
        if mesh.is_empty() {
            continue;
        }
        opaque += mesh.opaque.len();
        transparent += mesh.transparent.len();
        for v in [coord.x, coord.y, coord.z] {
            bytes.extend_from_slice(&v.to_le_bytes());
        }
        for layer in [&mesh.opaque, &mesh.transparent] {
            bytes.extend_from_slice(&(layer.len() as u32).to_le_bytes());
        }
        for layer in [&mesh.opaque, &mesh.transparent] {
            for face in &layer.faces {
                bytes.extend_from_slice(bytemuck::cast_slice(face));
            }
        }
    }
    println!(
        "{}: {} voxels in {} chunks -> {opaque} opaque + {transparent} transparent quads \
         ({} bytes of quads)",
        input.display(),
        scene.voxel_count,
        scene.world.iter().count(),
        8 * (opaque + transparent),
    );
    if opaque + transparent == 0 && scene.voxel_count > 0 {
        return Err("voxels but no quads".into());
    }
    if let Some(path) = output {
        std::fs::write(&path, &bytes)?;
        println!("wrote {}", path.display());
    }
    Ok(())
}
