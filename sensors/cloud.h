// One view of a scan: an organised point cloud with per-point ground truth.
#pragma once

#include "synth/types.h"

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <vector>

namespace grapebench {

struct OrganisedCloud {
  int width = 0, height = 0;
  // Per pixel, row-major (index = v * width + u). Positions and normals are in the
  // sensor frame (x right, y down, z forward), metres; invalid points are NaN.
  std::vector<Eigen::Vector3f> xyz;
  std::vector<std::array<std::uint8_t, 3>> rgb;
  std::vector<Eigen::Vector3f> normal;
  std::vector<std::uint8_t> label;   // Part of the surface the return came from
  std::vector<std::int32_t> berry;   // berry id (berries and their pedicels), else -1
  std::vector<std::uint8_t> valid;   // 1 when the sensor returns a point
  // Ground truth of the pixel's centre ray without noise or mixing: depth (z, m; 0 on
  // a miss) and the part hit, for scoring and for tests of the sensor artefacts.
  std::vector<float> true_depth;
  std::uint64_t rays_cast = 0;  // rays traced for this frame (for rays-per-second figures)

  void resize(int w, int h);
  std::size_t size() const { return static_cast<std::size_t>(width) * height; }
  std::size_t valid_count() const;
};

}  // namespace grapebench
