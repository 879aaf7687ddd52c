#!/usr/bin/env bash
# The main job: set-up, build, then `grapebench run` on the default suite.
# Extra arguments go to `grapebench run`.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${GRAPEBENCH_BUILD_DIR:-$here/build}"
"$here/scripts/setup.sh" "$build"
cd "$here"
"$build/bench/grapebench" run "$@"
