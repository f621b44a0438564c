//! Helpers shared by the storage, gather and codec tests: a small deterministic PRNG, random
//! edit scripts, brute-force recounts and a terrain generator.
#![allow(
    dead_code,
    reason = "each test binary uses a different subset of the helpers"
)]

use voxel_core::storage::{DenseChunk, PaletteChunk, VoxelStorage};
use voxel_core::{BlockId, ChunkSize, LocalPos};

/// xorshift64*: deterministic, good enough to scatter test edits.
#[derive(Clone, Debug)]
pub(crate) struct Rng(pub u64);

impl Rng {
    pub(crate) fn new(seed: u64) -> Self {
        Rng(seed | 1)
    }

    pub(crate) fn next_u64(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }

    /// Uniform in `0..n` (n > 0).
    pub(crate) fn below(&mut self, n: u64) -> u64 {
        self.next_u64() % n
    }

    pub(crate) fn local(&mut self, size: ChunkSize) -> LocalPos {
        let e = u64::from(size.edge());
        LocalPos {
            x: self.below(e) as u8,
            y: self.below(e) as u8,
            z: self.below(e) as u8,
        }
    }
}

/// One edit of a random script.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Op {
    Set(LocalPos, BlockId),
    Fill(BlockId),
    /// Set every voxel of the box `min..=max` (may be the whole chunk: collapses to uniform).
    Box(LocalPos, LocalPos, BlockId),
}

/// An id from a pool of `pool` ids: `0` (air) and `1..pool`, spread over the u16 range when the
/// pool is large.
pub(crate) fn pool_id(rng: &mut Rng, pool: u64) -> BlockId {
    let k = rng.below(pool);
    if pool > 64 {
        BlockId((k * 65_521 / pool.max(1)) as u16 + (k as u16 & 1))
    } else {
        BlockId(k as u16)
    }
}

/// A script of `n` edits with ids from a pool of `pool` ids.
pub(crate) fn script(seed: u64, size: ChunkSize, pool: u64, n: usize) -> Vec<Op> {
    let mut rng = Rng::new(seed);
    (0..n)
        .map(|_| match rng.below(1000) {
            0..=1 => Op::Fill(pool_id(&mut rng, pool)),
            2..=5 => {
                let (a, b) = (rng.local(size), rng.local(size));
                let min = LocalPos {
                    x: a.x.min(b.x),
                    y: a.y.min(b.y),
                    z: a.z.min(b.z),
                };
                let max = LocalPos {
                    x: a.x.max(b.x),
                    y: a.y.max(b.y),
                    z: a.z.max(b.z),
                };
                if rng.below(4) == 0 {
                    let last = (size.edge() - 1) as u8;
                    let whole = LocalPos {
                        x: last,
                        y: last,
                        z: last,
                    };
                    Op::Box(LocalPos::default(), whole, pool_id(&mut rng, pool))
                } else {
                    Op::Box(min, max, pool_id(&mut rng, pool))
                }
            }
            _ => Op::Set(rng.local(size), pool_id(&mut rng, pool)),
        })
        .collect()
}

/// Applies `op` to `s`; returns the old ids of every voxel it set, in order.
pub(crate) fn apply<S: VoxelStorage>(s: &mut S, op: Op, olds: &mut Vec<BlockId>) {
    olds.clear();
    match op {
        Op::Set(pos, id) => olds.push(s.set(pos, id).expect("position in range")),
        Op::Fill(id) => s.fill(id),
        Op::Box(min, max, id) => {
            for z in min.z..=max.z {
                for y in min.y..=max.y {
                    for x in min.x..=max.x {
                        let pos = LocalPos { x, y, z };
                        olds.push(s.set(pos, id).expect("position in range"));
                    }
                }
            }
        }
    }
}

/// Every voxel of `s` in linear order, read with `get`.
pub(crate) fn voxels_by_get<S: VoxelStorage>(s: &S) -> Vec<BlockId> {
    let size = s.size();
    let e = size.edge();
    let mut out = Vec::with_capacity(size.volume());
    for z in 0..e {
        for y in 0..e {
            for x in 0..e {
                out.push(s.get(LocalPos::new(x, y, z, size).unwrap()).unwrap());
            }
        }
    }
    out
}

/// The occupancy mask of row `(y, z)`, recounted voxel by voxel.
pub(crate) fn brute_mask<S: VoxelStorage>(s: &S, y: u32, z: u32) -> u64 {
    let size = s.size();
    (0..size.edge()).fold(0, |m, x| {
        let id = s.get(LocalPos::new(x, y, z, size).unwrap()).unwrap();
        m | (u64::from(!id.is_air()) << x)
    })
}

/// Checks masks, the non-air count, rows and the iterator of `s` against voxel-by-voxel reads.
pub(crate) fn check_consistent<S: VoxelStorage>(s: &S) -> Result<(), String> {
    let size = s.size();
    let e = size.edge();
    let voxels = voxels_by_get(s);
    let count = voxels.iter().filter(|v| !v.is_air()).count();
    if s.non_air_count() != count {
        return Err(format!(
            "non_air_count {} != recount {count}",
            s.non_air_count()
        ));
    }
    let mut row = vec![BlockId::AIR; e as usize];
    for z in 0..e {
        for y in 0..e {
            let mask = s.column_mask(y, z).unwrap();
            let brute = brute_mask(s, y, z);
            if mask != brute {
                return Err(format!(
                    "row ({y}, {z}): mask {mask:#x} != recount {brute:#x}"
                ));
            }
            s.copy_row(y, z, &mut row).unwrap();
            let start = size.linearize(0, y, z);
            if row[..] != voxels[start..start + e as usize] {
                return Err(format!("row ({y}, {z}): copy_row differs from get"));
            }
        }
    }
    for (i, (pos, id)) in s.iter().enumerate() {
        if pos.index(size) != Ok(i) || id != voxels[i] {
            return Err(format!("iter item {i} is ({pos:?}, {id:?})"));
        }
    }
    Ok(())
}

/// The narrowest width that holds `distinct` ids.
pub(crate) fn smallest_bits(distinct: usize) -> u8 {
    match distinct {
        1 => 0,
        2 => 1,
        3..=4 => 2,
        5..=16 => 4,
        17..=256 => 8,
        _ => 16,
    }
}

/// Distinct ids of a voxel list.
pub(crate) fn distinct(voxels: &[BlockId]) -> usize {
    let mut v = voxels.to_vec();
    v.sort_unstable();
    v.dedup();
    v.len()
}

/// Integer hash noise in 0..=255.
fn hash3(x: i64, y: i64, z: i64, salt: u64) -> u64 {
    let mut h = (x as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15)
        ^ (y as u64).wrapping_mul(0xC2B2_AE3D_27D4_EB4F)
        ^ (z as u64).wrapping_mul(0x1656_67B1_9E37_79F9)
        ^ salt;
    h ^= h >> 29;
    h = h.wrapping_mul(0xBF58_476D_1CE4_E5B9);
    h ^= h >> 32;
    h & 0xFF
}

/// Smooth 2D value noise in 0..1 at cell scale `scale`.
fn value_noise(x: i64, z: i64, scale: i64, salt: u64) -> f64 {
    let (cx, cz) = (x.div_euclid(scale), z.div_euclid(scale));
    let (fx, fz) = (
        x.rem_euclid(scale) as f64 / scale as f64,
        z.rem_euclid(scale) as f64 / scale as f64,
    );
    let s = |t: f64| t * t * (3.0 - 2.0 * t);
    let (sx, sz) = (s(fx), s(fz));
    let v = |dx: i64, dz: i64| hash3(cx + dx, 0, cz + dz, salt) as f64 / 255.0;
    let a = v(0, 0) + (v(1, 0) - v(0, 0)) * sx;
    let b = v(0, 1) + (v(1, 1) - v(0, 1)) * sx;
    a + (b - a) * sz
}

/// Heightmap terrain with layered materials, ore specks and caves: at most 16 distinct ids
/// (air, stone, dirt, grass, sand, water, bedrock, 3 ores, gravel, clay, snow).
pub(crate) fn terrain_chunk(size: ChunkSize, origin: [i64; 3], seed: u64) -> DenseChunk {
    let e = i64::from(size.edge());
    DenseChunk::from_fn(size, |p| {
        let (x, y, z) = (
            origin[0] + i64::from(p.x),
            origin[1] + i64::from(p.y),
            origin[2] + i64::from(p.z),
        );
        let h = (e as f64 * (0.25 + 0.5 * value_noise(x, z, 16, seed))
            + 4.0 * value_noise(x, z, 5, seed ^ 7)) as i64;
        let water_level = e * 2 / 5;
        let cave = hash3(x / 3, y / 3, z / 3, seed ^ 0xCA7E) < 40 && y < h - 2 && y > 1;
        let id = if y > h {
            if y <= water_level { 6 } else { 0 }
        } else if y == 0 {
            7
        } else if cave {
            0
        } else if y == h {
            if h <= water_level + 1 {
                5
            } else if h > e * 7 / 10 {
                12
            } else {
                3
            }
        } else if y > h - 4 {
            if h <= water_level + 1 { 11 } else { 2 }
        } else {
            match hash3(x, y, z, seed ^ 0x0E) {
                0..=2 => 8,
                3..=4 => 9,
                5 => 10,
                6..=9 => 13,
                _ => 1,
            }
        };
        BlockId(id)
    })
}

/// Applies a script to a dense and a palette chunk side by side; returns both.
pub(crate) fn run_script(
    size: ChunkSize,
    ops: &[Op],
) -> Result<(DenseChunk, PaletteChunk), String> {
    let mut dense = DenseChunk::new(size);
    let mut palette = PaletteChunk::new(size);
    let (mut a, mut b) = (Vec::new(), Vec::new());
    for (n, &op) in ops.iter().enumerate() {
        apply(&mut dense, op, &mut a);
        apply(&mut palette, op, &mut b);
        if a != b {
            return Err(format!("op {n} ({op:?}) returned different old ids"));
        }
    }
    Ok((dense, palette))
}
