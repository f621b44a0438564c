#!/usr/bin/env bash
# Installs the Khronos glTF validator that voxmesh's tests run (voxmesh/tests/khronos_validator.rs):
#   - node and npm from Debian's packages when either is missing;
#   - the npm package gltf-validator, pinned, under .tools/gltf-validator/ (git-ignored).
# Safe to run again: it installs only what is missing.
set -euo pipefail
cd "$(dirname "$0")/.."

VERSION=2.0.0-dev.3.10
DIR=.tools/gltf-validator

as_root() {
    if [ "$(id -u)" -eq 0 ]; then "$@"; elif command -v sudo >/dev/null 2>&1; then sudo "$@"; else
        echo "error: need root (or sudo) to run: $*" >&2
        exit 1
    fi
}

if ! command -v node >/dev/null 2>&1 || ! command -v npm >/dev/null 2>&1; then
    echo "setup: installing nodejs npm"
    as_root apt-get update -qq
    as_root env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends nodejs npm >/dev/null
fi

installed=$(node -e "try { console.log(require('./$DIR/node_modules/gltf-validator/package.json').version) } catch (e) {}")
if [ "$installed" != "$VERSION" ]; then
    echo "setup: installing gltf-validator $VERSION into $DIR"
    mkdir -p "$DIR"
    npm install --prefix "$DIR" --no-audit --no-fund --loglevel=error "gltf-validator@$VERSION" >/dev/null
fi
echo "setup: glTF validator $VERSION ok ($DIR)"
