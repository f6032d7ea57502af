#!/usr/bin/env bash
# The whole test suite: installs what is missing, builds with
# AddressSanitizer and UndefinedBehaviorSanitizer, and runs ctest once.
# Shared test geometry is read from $VDMESH_DATA (default ../shared/data).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
"$here/Resources/tools/install-deps.sh"
build="$here/build-test"
export VDMESH_DATA="${VDMESH_DATA:-$(cd "$here/.." && pwd)/shared/data}"
[ -d "$VDMESH_DATA" ] || echo "test.sh: no shared data at $VDMESH_DATA: the tests that need it will say so and skip"
# -O1 -g1: sanitizer builds of CGAL code are slow to compile; this keeps line
# numbers in the reports and the suite fast enough.
"$here/Resources/tools/build.sh" "$build" -DVDMESH_SANITIZE=ON -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG" -DVDMESH_DATA="$VDMESH_DATA"
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=0"
export LSAN_OPTIONS="suppressions=$here/tests/lsan.supp"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
cd "$build"
ctest --output-on-failure -j "$(nproc)" --timeout 1800
