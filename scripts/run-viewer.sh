#!/usr/bin/env bash
# The README's main command: sets the machine up, then runs the viewer on its built-in scene.
# Arguments are passed to the viewer (try --help). With a display it opens a window; without
# one it writes a PNG and prints where.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup-debian.sh >/dev/null
# Mesa's Vulkan loader layers complain on every device creation when this is unset (no login
# session, as in containers); a private empty folder is all they need.
if [ -z "${XDG_RUNTIME_DIR:-}" ]; then
    XDG_RUNTIME_DIR=$(mktemp -d)
    export XDG_RUNTIME_DIR
fi
# The `viewer` profile (root Cargo.toml): release optimizations without LTO or debug info, so
# the first build is short; the binary is target/viewer/viewer.
exec cargo run --profile viewer --locked -p viewer -- "$@"
