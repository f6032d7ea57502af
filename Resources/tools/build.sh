#!/usr/bin/env bash
# Configures and builds vdmesh into a build folder (default: build).
#   Resources/tools/build.sh [BUILD_DIR] [extra cmake options]
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
build="${1:-$here/build}"
shift || true
jobs="${VDMESH_JOBS:-$(nproc)}"
cmake -S "$here" -B "$build" -DCMAKE_BUILD_TYPE=Release "$@" >/dev/null
cmake --build "$build" -j "$jobs"
