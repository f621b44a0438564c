//! The overlay's controls as plain state: mesher mode, far draws, error budget and layers.
//! The window edits a copy with egui and hands it to
//! [`StreamedView::apply`](crate::view::StreamedView::apply); tests drive the same function
//! without a window.

use gpu_backend::render::far::FarRequest;

use crate::stream::{Layers, MesherMode, StreamSettings};

/// What the user can change while the viewer runs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Controls {
    /// How nodes are meshed (a change re-meshes the terrain in the background).
    pub mesher: MesherMode,
    /// The far-draw path (a change makes a new renderer and re-streams into it).
    pub far: FarRequest,
    /// The error budget, pixels (a change re-plans; no re-meshing).
    pub budget_px: f32,
    /// The layers uploaded (a change re-streams the terrain without the hidden ones).
    pub layers: Layers,
}

/// The slider's range of error budgets, pixels.
pub const BUDGET_RANGE: std::ops::RangeInclusive<f32> = 0.25..=16.0;

impl Controls {
    /// The controls that `settings` stand for.
    pub fn of(settings: &StreamSettings) -> Controls {
        Controls {
            mesher: settings.mesher,
            far: settings.far,
            budget_px: settings.budget_px,
            layers: settings.layers,
        }
    }

    /// `settings` with these controls applied.
    pub fn applied_to(&self, settings: &StreamSettings) -> StreamSettings {
        StreamSettings {
            mesher: self.mesher,
            far: self.far,
            budget_px: self.budget_px,
            layers: self.layers,
            ..settings.clone()
        }
    }

    /// True when going from `self` to `other` changes what nodes hold (mesher, layers) or
    /// how they are drawn (far path): a new streamer is needed, not just a new plan.
    pub fn needs_restream(&self, other: &Controls) -> bool {
        self.mesher != other.mesher || self.far != other.far || self.layers != other.layers
    }
}
