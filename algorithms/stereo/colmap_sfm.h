// Camera poses from images alone, as seed 004's pipeline got them (Dey et al. 2012,
// Sect. 3.1 used Bundler; Debian packages COLMAP 3.8, CPU only): SIFT features,
// sequential matching and incremental mapping with the intrinsics held fixed, run as
// the `colmap` program in a private temporary folder.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "synth/confined_program.h"
#include "algorithms/stereo_pair.h"
#include "synth/param_table.h"

namespace grapebench {

struct ColmapParams {
  std::string program = "colmap";  // looked up in PATH
  double timeout = 600;            // s, the whole run; then its process group is killed
  int overlap = 5;                 // sequential matcher: each image against this many next ones
  ProgramLimits::Sandbox sandbox = ProgramLimits::Sandbox::Bwrap;
  bool repeatable = true;  // preload algorithms/stereo/colmap_seed_shim.cpp: the same images give the same poses
};
const ParamTable<ColmapParams>& colmap_param_table();
// How each COLMAP step is confined (synth/confined_program.h): the sandbox, its CPU time,
// the seed shim it preloads.
ProgramLimits colmap_program_limits(const ColmapParams& p);

struct ColmapPoses {
  // Per image: camera to COLMAP's world (arbitrary similarity frame), or nullopt when
  // the mapper did not register it.
  std::vector<std::optional<Eigen::Isometry3d>> poses;
  int registered = 0;
  int points3d = 0;  // sparse points of the model kept
  std::string log_tail;
};

// images: the pass's views (W x H x 3, one camera); fx, fy, cx, cy in pixels with rays
// through (u + 0.5, v + 0.5) at cx (COLMAP's convention too). COLMAP runs on one
// thread with `seed` as its --random_seed and, when `repeatable`, with the seed shim
// preloaded; without the shim two runs gave slightly different poses (0.149 and 0.124
// deg mean rotation error). Throws
// InputError when the program cannot start, fails, times out, or writes a model it
// cannot read.
ColmapPoses colmap_sfm(const std::vector<RgbImage>& images, double fx, double fy, double cx, double cy,
                       const ColmapParams& p, std::uint64_t seed);

// COLMAP's images.txt (IMAGE_ID QW QX QY QZ TX TY TZ CAMERA_ID NAME, then a points
// line) as camera-to-world poses by image name; exposed for tests. Throws InputError
// naming the line on malformed input.
std::vector<std::pair<std::string, Eigen::Isometry3d>> parse_colmap_images(const std::string& text);

}  // namespace grapebench
