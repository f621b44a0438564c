//! Window or PNG: the viewer's mode from its flags and the environment.

/// What the viewer does.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mode {
    /// Open a window. `forced` (`--window`): a failure is an error; otherwise the viewer falls
    /// back to the PNG.
    Window {
        /// `--window` was given.
        forced: bool,
    },
    /// Render one frame to a PNG.
    Headless,
}

/// `--window` forces a window; `--headless` forces the PNG; otherwise a window when a display
/// exists (`has_display`, see [`display_present`]).
pub fn choose_mode(headless: bool, window: bool, has_display: bool) -> Mode {
    if window {
        Mode::Window { forced: true }
    } else if headless || !has_display {
        Mode::Headless
    } else {
        Mode::Window { forced: false }
    }
}

/// A display server is named in the environment: `DISPLAY` (X11) or `WAYLAND_DISPLAY`, set and
/// not empty.
pub fn display_present() -> bool {
    ["DISPLAY", "WAYLAND_DISPLAY"]
        .iter()
        .any(|name| std::env::var_os(name).is_some_and(|v| !v.is_empty()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn flags_and_display_pick_the_mode() {
        assert_eq!(choose_mode(false, false, false), Mode::Headless);
        assert_eq!(
            choose_mode(false, false, true),
            Mode::Window { forced: false }
        );
        assert_eq!(choose_mode(true, false, true), Mode::Headless);
        assert_eq!(
            choose_mode(false, true, false),
            Mode::Window { forced: true }
        );
    }
}
