#!/usr/bin/env bash
# The whole test suite: set-up, build, then every test through ctest.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${GRAPEBENCH_BUILD_DIR:-$here/build}"
"$here/scripts/setup.sh" "$build"
cd "$build"
ctest --output-on-failure --parallel "$(nproc)" --timeout 900
