//! Writing outputs all or nothing: every file goes to a temporary file beside its target, and
//! only when all are written are they renamed into place. On any failure before that, the
//! temporary files are removed and no target is touched.

use std::io::Write;
use std::path::{Path, PathBuf};

use tempfile::NamedTempFile;

use crate::Error;

/// Files written so far, waiting to be renamed into place.
#[derive(Default)]
pub struct Outputs {
    pending: Vec<(NamedTempFile, PathBuf)>,
}

impl Outputs {
    /// No files yet.
    pub fn new() -> Outputs {
        Outputs::default()
    }

    /// Writes `bytes` to a temporary file in `target`'s folder; returns the byte count.
    pub fn write(&mut self, target: &Path, bytes: &[u8]) -> Result<u64, Error> {
        let io = |source| Error::Write {
            path: target.to_path_buf(),
            source,
        };
        let dir = match target.parent() {
            Some(d) if !d.as_os_str().is_empty() => d,
            _ => Path::new("."),
        };
        let mut file = NamedTempFile::new_in(dir).map_err(io)?;
        file.write_all(bytes).map_err(io)?;
        file.as_file().sync_all().map_err(io)?;
        self.pending.push((file, target.to_path_buf()));
        Ok(bytes.len() as u64)
    }

    /// Renames every file into place, in the order written. A failure names the target; the
    /// files not yet renamed are removed.
    pub fn commit(self) -> Result<(), Error> {
        for (file, target) in self.pending {
            file.persist(&target).map_err(|e| Error::Write {
                path: target.clone(),
                source: e.error,
            })?;
        }
        Ok(())
    }
}
