//! The overlay's content: the statistics lines, the streamed terrain's controls (edited in
//! place by egui widgets), the loading banner, the last message and the control hints; and
//! the egui UI that shows them.

use egui::{Align2, Area, Context, Id, RichText, Slider};

use crate::controls::{BUDGET_RANGE, Controls};
use crate::stream::MesherMode;
use crate::stream::settings::FAR_CHOICES;

/// The control hints shown at the bottom of the window.
pub(super) const HINTS: &str = "W/A/S/D move · Space/Shift up/down · drag to look · wheel: speed · \
                         F1 overlay · F3 wireframe · F12 screenshot · Esc quit";

/// What the overlay shows this frame.
#[derive(Clone, Debug, Default, PartialEq)]
pub(super) struct Panel {
    /// Show the overlay (F1): statistics, controls, hints and the last message. Without it
    /// only the loading banner is drawn.
    pub show: bool,
    /// Statistics, one line each.
    pub lines: Vec<String>,
    /// The streamed terrain's controls, edited in place (`None` for a fixed scene).
    pub controls: Option<Controls>,
    /// Shown even with the overlay hidden, in the middle: the first view's loading progress.
    pub banner: Option<String>,
    /// The last message: a screenshot's path, a refused control.
    pub message: Option<String>,
    /// Draw meshes as their quads' edges (F3, or the overlay's checkbox).
    pub wireframe: bool,
    /// Grass and flowers drawn (the overlay's checkbox; the renderer refuses it without a
    /// grass pass).
    pub grass: bool,
}

/// Builds the overlay's UI for `panel` into `ctx` (egui edits `panel.controls`).
pub(super) fn ui(ctx: &Context, panel: &mut Panel) {
    if let Some(banner) = &panel.banner {
        Area::new(Id::unique("banner"))
            .anchor(Align2::CENTER_CENTER, [0.0, 0.0])
            .show(ctx, |ui| {
                ui.heading(RichText::new(banner).strong());
            });
    }
    if !panel.show {
        return;
    }
    Area::new(Id::unique("hints"))
        .anchor(Align2::LEFT_BOTTOM, [8.0, -6.0])
        .show(ctx, |ui| {
            if let Some(message) = &panel.message {
                ui.label(RichText::new(message).strong());
            }
            ui.label(HINTS);
        });
    egui::Window::new("viewer")
        .resizable(false)
        .default_pos([8.0, 8.0])
        .show(ctx, |ui| {
            for line in &panel.lines {
                ui.monospace(line);
            }
            ui.checkbox(&mut panel.wireframe, "wireframe (F3)");
            ui.checkbox(&mut panel.grass, "grass");
            if let Some(controls) = &mut panel.controls {
                ui.separator();
                controls_ui(ui, controls);
            }
        });
}

/// The streamed terrain's controls.
fn controls_ui(ui: &mut egui::Ui, c: &mut Controls) {
    ui.horizontal(|ui| {
        ui.label("mesher");
        for mode in MesherMode::ALL {
            ui.selectable_value(&mut c.mesher, mode, mode.name());
        }
    });
    ui.horizontal(|ui| {
        ui.label("far draws");
        for (name, far) in FAR_CHOICES {
            ui.selectable_value(&mut c.far, far, name);
        }
    });
    ui.add(
        Slider::new(&mut c.budget_px, BUDGET_RANGE)
            .logarithmic(true)
            .text("error budget, px"),
    );
    ui.horizontal(|ui| {
        ui.label("layers");
        ui.checkbox(&mut c.layers.opaque, "opaque");
        ui.checkbox(&mut c.layers.transparent, "transparent");
        ui.checkbox(&mut c.layers.smooth, "smooth");
    });
}
