//! Running out of GPU memory on the way: the gigabuffers refuse allocations past a limit
//! below what the flight's view needs (`test_support::refuse_node_bytes_past`, the refusal a
//! device's out-of-memory gives, on lavapipe, which never runs out), and the flight still
//! completes: the streamer coarsens the view until it fits, no frame draws a hole, nothing
//! panics, and the report names the refusal.
//!
//! The limit is process-wide, so this file is a test binary of its own.

use gpu_backend::DeviceOptions;
use gpu_backend::test_support::{headless_or_skip, refuse_node_bytes_past};
use viewer::flight::{FlightPath, fly};
use viewer::stream::StreamSettings;

/// A small view lavapipe streams in seconds.
fn settings() -> StreamSettings {
    StreamSettings {
        radius: 192,
        memory_bytes: 64 << 20,
        max_nodes: 4096,
        ..StreamSettings::default()
    }
}

const SIZE: (u32, u32) = (160, 90);
const SECONDS: f64 = 1.0;

#[test]
fn a_flight_through_refused_allocations_coarsens_and_draws_no_hole() {
    let Some(ctx) = headless_or_skip(&DeviceOptions::default()) else {
        return;
    };
    let path = FlightPath::over_origin(70.0);
    let free = fly(&ctx, &settings(), &path, SECONDS, SIZE, |_| {}).expect("the free flight");
    assert_eq!(free.frames_with_holes, 0);
    assert_eq!(free.memory_note, None, "the free flight never runs out");
    let needed = free.first_view_bytes;
    assert!(needed > 0, "the first view holds node data");

    // Less than the first view needs: every view of the flight is over the limit.
    refuse_node_bytes_past(Some(needed / 2));
    let tight = fly(&ctx, &settings(), &path, SECONDS, SIZE, |_| {});
    refuse_node_bytes_past(None);
    let tight = tight.expect("the flight completes under the limit");
    assert_eq!(tight.frames_with_holes, 0, "no frame draws a hole");
    let floor = tight.memory_floor_px.expect("the memory raised the budget");
    assert!(floor > settings().budget_px, "coarser: {floor} px");
    let note = tight.memory_note.clone().expect("the refusal is named");
    assert!(
        note.contains("injected") && note.contains("refused"),
        "the note names the refusal: {note}"
    );
    assert!(
        tight.lines().iter().any(|l| l.contains(&note)),
        "the report prints it: {:?}",
        tight.lines()
    );
}
