#!/usr/bin/env bash
# The main job on the bundled example: installs what is missing, builds, and
# meshes Resources/examples/bracket.obj into out/bracket.vtu with a report.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
"$here/Resources/tools/install-deps.sh"
"$here/Resources/tools/build.sh" "$here/build"
mkdir -p "$here/out"
"$here/build/bin/vdmesh" mesh "$here/Resources/examples/bracket.obj" -o "$here/out/bracket.vtu" \
  --report "$here/out/bracket.report.json"
"$here/build/bin/vdmesh" info "$here/out/bracket.vtu"
echo "mesh: out/bracket.vtu   report: out/bracket.report.json"
