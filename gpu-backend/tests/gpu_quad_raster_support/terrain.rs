//! A small heightmap terrain meshed into greedy quads by hand (the meshers are not a dependency
//! of this crate): per node of 16 x 16 columns, the tops merged into greedy rectangles (they
//! meet at T-junctions) and one side quad per column face above a lower neighbour, with random
//! corner AO. Neighbouring columns across node borders agree, so the surface is closed where
//! seen from above; bottoms are not meshed.

use voxel_core::formats::{PackedQuad, PackedQuadFields};
use voxel_core::{BlockId, FaceDirection};

/// Edge of a node, cells.
const EDGE: i32 = 16;

fn hash(mut v: u64) -> u64 {
    v ^= v >> 33;
    v = v.wrapping_mul(0xff51_afd7_ed55_8ccd);
    v ^= v >> 33;
    v = v.wrapping_mul(0xc4ce_b9fe_1a85_ec53);
    v ^ (v >> 33)
}

/// Height in cells (1..=`max`) of column `(x, z)` of the level's cell grid: plateaus of 4 x 4
/// columns with a few single-column bumps, so tops merge into rectangles of several sizes.
pub(crate) fn height(seed: u64, level: u32, x: i32, z: i32, max: u32) -> u32 {
    let key = |a: i32, b: i32, salt: u64| {
        hash(seed ^ salt ^ (u64::from(a as u32) << 32 | u64::from(b as u32)) ^ u64::from(level))
    };
    let plateau = key(x.div_euclid(4), z.div_euclid(4), 0x9e37) % u64::from(max);
    let bump = u64::from(key(x, z, 0x51ed) % 7 == 0);
    (1 + plateau + bump).min(u64::from(max)) as u32
}

fn quad(
    position: [u32; 3],
    size: [u32; 2],
    face: FaceDirection,
    seed: u64,
    block: u16,
) -> PackedQuad {
    let ao: [u8; 4] = std::array::from_fn(|k| (hash(seed ^ (k as u64 * 0x1234_5678)) % 4) as u8);
    PackedQuad::encode(&PackedQuadFields {
        position,
        width: size[0],
        height: size[1],
        face,
        ao,
        block: BlockId(block),
    })
    .expect("a valid quad")
}

/// The quads of node `(cx, cz)` (chunk row y = 0) at `level` of the terrain `seed`, heights
/// 1..=`max` cells.
pub(crate) fn node_quads(seed: u64, level: u32, cx: i32, cz: i32, max: u32) -> Vec<PackedQuad> {
    let h = |x: i32, z: i32| height(seed, level, cx * EDGE + x, cz * EDGE + z, max);
    let mut out = Vec::new();
    // Tops: greedy rectangles of equal height.
    let mut used = [[false; 16]; 16];
    for z in 0..EDGE {
        for x in 0..EDGE {
            if used[z as usize][x as usize] {
                continue;
            }
            let top = h(x, z);
            let mut w = 1;
            while x + w < EDGE && !used[z as usize][(x + w) as usize] && h(x + w, z) == top {
                w += 1;
            }
            let mut d = 1;
            while z + d < EDGE
                && (x..x + w).all(|i| !used[(z + d) as usize][i as usize] && h(i, z + d) == top)
            {
                d += 1;
            }
            for row in &mut used[z as usize..(z + d) as usize] {
                row[x as usize..(x + w) as usize].fill(true);
            }
            let salt = hash(seed ^ u64::from((cx * 977 + cz * 131 + x * 17 + z) as u32));
            out.push(quad(
                [x as u32, top - 1, z as u32],
                [w as u32, d as u32],
                FaceDirection::PosY,
                salt,
                10 + top as u16,
            ));
        }
    }
    // Sides: one quad per column face above a lower neighbour.
    let sides = [
        (FaceDirection::PosX, 1, 0),
        (FaceDirection::NegX, -1, 0),
        (FaceDirection::PosZ, 0, 1),
        (FaceDirection::NegZ, 0, -1),
    ];
    for z in 0..EDGE {
        for x in 0..EDGE {
            let top = h(x, z);
            for (k, &(face, dx, dz)) in sides.iter().enumerate() {
                let below = h(x + dx, z + dz);
                if below >= top {
                    continue;
                }
                // X faces: width along z, height along y; Z faces: width along x.
                let salt = hash(seed ^ u64::from((x * 31 + z * 7 + k as i32) as u32) ^ 0xabc);
                out.push(quad(
                    [x as u32, below, z as u32],
                    [1, top - below],
                    face,
                    salt,
                    40 + k as u16,
                ));
            }
        }
    }
    out
}
