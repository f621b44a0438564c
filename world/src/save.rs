//! Saving a [`World`] as a folder of region files and loading it back.
//!
//! ```text
//!  DIR/world.vxw         magic "VXWD", version u16, chunk edge u8, crc32 of the 7 bytes before
//!  DIR/r.X.Y.Z.vxr       the edited chunks of region (X, Y, Z) (crate::region)
//!  DIR/*.tmp             a write in progress, or one a crash interrupted: never read
//! ```
//!
//! Only edited chunks are stored: the base regenerates the rest. A save rewrites each region
//! holding a chunk edited since the last save, whole, atomically: the bytes go to a temporary
//! file beside it, which is flushed to disk (`fsync`), renamed over the old file, and the
//! folder is flushed so the rename itself survives a power cut. A process killed at any point
//! leaves every region file either as the last completed save wrote it or as the interrupted
//! save did, never a mix, so a load always succeeds and never loses an edit of a completed save.

use std::fs;
use std::io::Write;
use std::path::{Path, PathBuf};

use voxel_core::{ChunkCoord, ChunkSize};

use crate::region::{decode_region, encode_region, region_of};
use crate::{Base, ChunkFault, World, WorldError};

/// The world file's name inside a world folder.
pub const WORLD_FILE: &str = "world.vxw";
const WORLD_MAGIC: [u8; 4] = *b"VXWD";
const WORLD_VERSION: u16 = 1;

/// What a load found besides the chunks it restored.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct LoadReport {
    /// Region files read.
    pub regions: usize,
    /// Chunks restored.
    pub chunks: usize,
    /// Chunks that did not load, with their region file; the world holds the base there.
    pub faults: Vec<(PathBuf, ChunkFault)>,
}

fn io(path: &Path) -> impl FnOnce(std::io::Error) -> WorldError + '_ {
    move |error| WorldError::Io {
        path: path.to_path_buf(),
        error,
    }
}

/// Writes `bytes` to `path` atomically: a temporary file in the same folder, flushed, renamed
/// over `path`, then the folder flushed.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), WorldError> {
    let dir = path.parent().unwrap_or(Path::new("."));
    let mut tmp = path.as_os_str().to_owned();
    tmp.push(".tmp");
    let tmp = PathBuf::from(tmp);
    let mut file = fs::File::create(&tmp).map_err(io(&tmp))?;
    file.write_all(bytes).map_err(io(&tmp))?;
    file.sync_all().map_err(io(&tmp))?;
    drop(file);
    fs::rename(&tmp, path).map_err(io(path))?;
    fs::File::open(dir)
        .and_then(|d| d.sync_all())
        .map_err(io(dir))?;
    Ok(())
}

fn region_name(r: [i32; 3]) -> String {
    format!("r.{}.{}.{}.vxr", r[0], r[1], r[2])
}

fn parse_region_name(name: &str) -> Option<[i32; 3]> {
    let rest = name.strip_prefix("r.")?.strip_suffix(".vxr")?;
    let mut parts = rest.split('.').map(|p| p.parse::<i32>().ok());
    let r = [parts.next()??, parts.next()??, parts.next()??];
    parts.next().is_none().then_some(r)
}

fn world_file_bytes(size: ChunkSize) -> Vec<u8> {
    let mut b = WORLD_MAGIC.to_vec();
    b.extend_from_slice(&WORLD_VERSION.to_le_bytes());
    b.push(size.edge() as u8);
    let crc = crc32fast::hash(&b);
    b.extend_from_slice(&crc.to_le_bytes());
    b
}

/// Reads a world folder's chunk size from its world file.
pub fn read_world_file(dir: &Path) -> Result<ChunkSize, WorldError> {
    let path = dir.join(WORLD_FILE);
    let bytes = fs::read(&path).map_err(io(&path))?;
    let refuse = |reason: String| WorldError::WorldFile {
        path: path.clone(),
        reason,
    };
    if bytes.len() != 11 {
        return Err(refuse(format!("{} bytes, expected 11", bytes.len())));
    }
    if bytes[..4] != WORLD_MAGIC {
        return Err(refuse("not a world file (magic)".into()));
    }
    let version = u16::from_le_bytes([bytes[4], bytes[5]]);
    if version != WORLD_VERSION {
        return Err(refuse(format!(
            "version {version}, this build reads {WORLD_VERSION}"
        )));
    }
    let stored = u32::from_le_bytes([bytes[7], bytes[8], bytes[9], bytes[10]]);
    if crc32fast::hash(&bytes[..7]) != stored {
        return Err(refuse("checksum does not match".into()));
    }
    ChunkSize::from_edge(u32::from(bytes[6])).map_err(|e| refuse(e.to_string()))
}

impl<B: Base> World<B> {
    /// Saves the world into folder `dir` (created if missing): the world file when it is not
    /// there, then every region holding a chunk edited since the last save or load, each
    /// written atomically. Returns the region files written.
    pub fn save(&mut self, dir: &Path) -> Result<usize, WorldError> {
        fs::create_dir_all(dir).map_err(io(dir))?;
        let world_file = dir.join(WORLD_FILE);
        if !world_file.exists() {
            write_atomic(&world_file, &world_file_bytes(self.size()))?;
        }
        let mut regions: Vec<[i32; 3]> = self.unsaved().map(region_of).collect();
        regions.sort_unstable();
        regions.dedup();
        let empty = voxel_core::storage::PaletteChunk::new(self.size());
        for &r in &regions {
            let chunks: Vec<(ChunkCoord, &voxel_core::storage::PaletteChunk)> = self
                .edited()
                .filter(|&c| region_of(c) == r)
                .map(|c| (c, self.chunks().get(c).unwrap_or(&empty)))
                .collect();
            let bytes = encode_region(r, self.size(), &chunks);
            write_atomic(&dir.join(region_name(r)), &bytes)?;
        }
        self.mark_saved();
        Ok(regions.len())
    }

    /// Loads the world saved in `dir` over `base`, with dirty sets up to level `top`. A region
    /// file that cannot be trusted refuses the load by its name ([`WorldError::Region`]); a
    /// chunk that does not load is listed in the report and the others load.
    pub fn load(base: B, dir: &Path, top: u32) -> Result<(World<B>, LoadReport), WorldError> {
        let size = read_world_file(dir)?;
        let mut world = World::new(base, size, top)?;
        let mut report = LoadReport::default();
        let mut entries: Vec<(PathBuf, [i32; 3])> = Vec::new();
        for entry in fs::read_dir(dir).map_err(io(dir))? {
            let entry = entry.map_err(io(dir))?;
            let name = entry.file_name();
            if let Some(r) = name.to_str().and_then(parse_region_name) {
                entries.push((entry.path(), r));
            }
        }
        entries.sort();
        for (path, r) in entries {
            let bytes = fs::read(&path).map_err(io(&path))?;
            let region = decode_region(&bytes, r, size).map_err(|error| WorldError::Region {
                path: path.clone(),
                error,
            })?;
            report.regions += 1;
            for (coord, chunk) in region.chunks {
                world.insert_edited(coord, chunk)?;
                report.chunks += 1;
            }
            report
                .faults
                .extend(region.faults.into_iter().map(|f| (path.clone(), f)));
        }
        world.mark_saved();
        Ok((world, report))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn region_names_round_trip_and_others_are_not_regions() {
        assert_eq!(
            parse_region_name(&region_name([-3, 0, 12])),
            Some([-3, 0, 12])
        );
        for other in [
            "r.1.2.vxr",
            "r.1.2.3.4.vxr",
            "r.1.2.3.vxr.tmp",
            "world.vxw",
            "r.a.2.3.vxr",
        ] {
            assert_eq!(parse_region_name(other), None, "{other}");
        }
    }
}
