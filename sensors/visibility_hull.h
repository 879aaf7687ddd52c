// The visibility hull of a capture rig: the space inside the bunch's bounding box that
// no camera of the rig can see, because every segment from a camera centre to it is
// blocked (or it lies outside every image). It contains the solid. What it adds (the
// pockets between berries hidden from every viewpoint, the shadows behind the bunch)
// is space that no reconstruction from those views can tell from the solid: its
// volume is the floor of an estimator that does not invent geometry. This is
// Laurentini's visual hull (1994) with depth: lines of sight, not silhouettes.
#pragma once

#include "sensors/camera.h"

#include <array>
#include <vector>

namespace grapebench {

struct VisibilityHullParams {
  double voxel = 0.001;   // m, sampling step of the box, [1e-4, 0.05]; at most 2e8 samples
  double margin = 0.003;  // m, added around the bunch's bounding box on every side, [0, 0.5]
};

struct VisibilityHull {
  double volume = 0;            // m3: hidden samples x voxel^3 (one sample per voxel centre)
  double box_volume = 0;        // m3: the sampled box
  std::size_t samples = 0;      // voxel centres in the box
  std::size_t hidden = 0;       // of them, seen by no camera
  std::uint64_t segments = 0;   // line-of-sight segments traced
};

// Samples the box of every berry and stem of `scene`'s bunch (plus `margin`) at voxel
// centres; a sample is seen when the segment from some camera centre to it is
// unblocked (bunch, foliage or background plane) and it projects inside that camera's
// image. Deterministic at any thread count. Throws InputError for no cameras, a bunch
// with no parts, or parameters out of range (naming the parameter).
VisibilityHull visibility_hull(const RayScene& scene, const std::vector<Camera>& cameras,
                               const VisibilityHullParams& params = {});

}  // namespace grapebench
