#!/usr/bin/env bash
# Installs every Debian package grapebench needs (idempotent), then configures and
# builds with ccache. Usage: scripts/setup.sh [build-dir] [extra cmake args...]
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${1:-$here/build}"
shift || true

packages=(
  build-essential cmake ninja-build ccache pkg-config git
  lld  # the linker (CMakeLists.txt: 7.4 s -> 0.4 s per executable against PCL and VTK)
  libeigen3-dev libcgal-dev libgmp-dev libmpfr-dev libboost-dev libtbb-dev
  libembree-dev libopenmesh-dev libpcl-dev libosmesa6-dev libpng-dev
  libyaml-cpp-dev nlohmann-json3-dev libcli11-dev
  libgtest-dev libbenchmark-dev
  libopencv-imgproc-dev  # seed 001's image steps (core + imgproc; not the 270 MiB metapackage)
  libopencv-imgcodecs-dev  # the colour camera's JPEG (sensors/render/develop_image.cpp)
  libopencv-calib3d-dev libopencv-ml-dev  # seed 004: StereoSGBM, EM (the GMM baseline)
  libsvm-dev libnanoflann-dev  # seed 004: the SVM; k-d trees of the per-point features
  colmap  # seed 004: poses from the images (sparse SfM, CPU; run as a program)
  python3-open3d python3-jsonschema  # the external-estimator example, its tests and the protocol schema check
  libopen3d-dev   # benchmark only: bench/perf/open3d_perf.cpp compares with Open3D
  chromium        # the report's browser test (headless)
  libjs-three     # the report's 3D view of a scan against its ground-truth mesh (inlined)
  python3-pandas  # the README's example of reading results.csv (tested)
  python3-opencv  # the dataset viewer and the external detector baseline (scripts/coco_view.py, tests)
  bubblewrap      # external programs run in a sandbox (synth/confined_program.h)
  clang libfuzzer-14-dev  # scripts/fuzz.sh and the fuzz targets' short runs in the test suite
  slurm-wlm munge  # tests/bench/slurm: a one-node Slurm cluster runs scripts/slurm_sweep.sh (daemons only in the test)
  pybind11-dev python3-dev python3-pytest python3-venv  # the Python package (python/, docs/python.md)
  blender  # renderer: cycles, the physically based reference (sensors/render/cycles_scene.py), headless
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "setup: installing ${missing[*]}"
  sudo=""
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  export DEBIAN_FRONTEND=noninteractive
  $sudo apt-get update -qq
  $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
else
  echo "setup: all ${#packages[@]} Debian packages present"
fi

export CCACHE_DIR="${CCACHE_DIR:-$HOME/.cache/ccache}"
# Paths relative to the checkout, so a fresh clone elsewhere (CI) hits the same cache.
export CCACHE_BASEDIR="${CCACHE_BASEDIR:-$here}"
# With -g (the sanitizer build's RelWithDebInfo) ccache also hashes the working
# directory, so each clone's build folder missed; objects differ then only in DWARF's
# comp_dir (the paths it records are relative to the checkout). docs/harness.md,
# "Compiler cache".
export CCACHE_NOHASHDIR="${CCACHE_NOHASHDIR:-1}"
jobs="$(nproc)"
cmake -S "$here" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE="${CMAKE_BUILD_TYPE:-Release}" "$@" >/dev/null
cmake --build "$build" --parallel "$jobs"
