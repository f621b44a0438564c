#!/usr/bin/env bash
# The README's main command: sets the machine up, then runs the viewer on its built-in scene.
# Arguments are passed to the viewer (try --help). With a display it opens a window; without
# one it writes a PNG and prints where.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup-debian.sh >/dev/null
exec cargo run --release --locked -p viewer -- "$@"
