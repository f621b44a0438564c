//! Screenshots: the renderer's last frame (without the overlay) read back and written as a
//! PNG of the frame's size, under a name no earlier screenshot took.

use std::fmt;
use std::path::{Path, PathBuf};

use gpu_backend::png::encode_png;
use gpu_backend::render::{RenderError, Renderer};

/// Why a screenshot was not written.
#[derive(Debug)]
#[non_exhaustive]
pub enum ScreenshotError {
    /// Reading the frame back failed.
    Read(RenderError),
    /// Encoding the PNG failed (why).
    Encode(String),
    /// The folder or the file could not be written.
    Write(PathBuf, std::io::Error),
}

impl fmt::Display for ScreenshotError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ScreenshotError::Read(e) => write!(f, "reading the frame back: {e}"),
            ScreenshotError::Encode(why) => write!(f, "encoding the PNG: {why}"),
            ScreenshotError::Write(path, e) => write!(f, "writing {}: {e}", path.display()),
        }
    }
}

impl std::error::Error for ScreenshotError {}

/// Writes `renderer`'s last frame to `dir/screenshot-N.png` (the first free `N` from 1;
/// `dir` is created if missing) and returns the path.
pub fn save_screenshot(renderer: &Renderer, dir: &Path) -> Result<PathBuf, ScreenshotError> {
    let image = renderer.read_image().map_err(ScreenshotError::Read)?;
    let targets = renderer.targets();
    let png = encode_png(targets.width, targets.height, &image.rgba)
        .map_err(|e| ScreenshotError::Encode(e.to_string()))?;
    std::fs::create_dir_all(dir).map_err(|e| ScreenshotError::Write(dir.to_owned(), e))?;
    let mut n = 1u32;
    loop {
        let path = dir.join(format!("screenshot-{n}.png"));
        // `create_new` claims the name atomically, so two viewers never overwrite each other.
        match std::fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(&path)
        {
            Ok(mut file) => {
                use std::io::Write;
                file.write_all(&png)
                    .map_err(|e| ScreenshotError::Write(path.clone(), e))?;
                return Ok(path);
            }
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => n += 1,
            Err(e) => return Err(ScreenshotError::Write(path, e)),
        }
    }
}
