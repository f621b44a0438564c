//! Writing outputs all or nothing: every file goes to a temporary file beside its target, and
//! only when all are written are they renamed into place. On any failure before that, the
//! temporary files are removed and no target is touched.
//!
//! The temporary file gets the mode a plain `File::create` of the target would: a new file's
//! `0o666` less the umask (the mode is asked for at creation, so the kernel applies the
//! umask), an existing file's own mode. So a web server or another user reads the output as
//! it would any other tool's, not only its owner (a temporary file's default is `0o600`).

use std::io::{self, Write};
use std::path::{Path, PathBuf};

use tempfile::NamedTempFile;

use crate::Error;

/// Files written so far, waiting to be renamed into place.
#[derive(Debug, Default)]
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
        let mut file = temp_file_beside(target, dir).map_err(io)?;
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

/// A temporary file in `dir` with the mode `File::create(target)` would give (see the
/// [module docs](self)).
fn temp_file_beside(target: &Path, dir: &Path) -> io::Result<NamedTempFile> {
    let mut builder = tempfile::Builder::new();
    builder.prefix(".voxmesh-");
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        builder.permissions(std::fs::Permissions::from_mode(0o666));
        let file = builder.tempfile_in(dir)?;
        // An existing target keeps its mode through `File::create`: the umask is not applied
        // to it, so it is set after creation.
        if let Ok(existing) = std::fs::metadata(target)
            && existing.is_file()
        {
            let mode = existing.permissions().mode() & 0o777;
            file.as_file()
                .set_permissions(std::fs::Permissions::from_mode(mode))?;
        }
        Ok(file)
    }
    #[cfg(not(unix))]
    {
        let _ = target;
        builder.tempfile_in(dir)
    }
}
