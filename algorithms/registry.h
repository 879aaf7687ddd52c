// The estimator and pipeline-step registries: scene files name them by `type`
// (Mitsuba's `type=`, pbrt's Create), through the one Registry template of
// synth/registry.h. Adding an estimator is its file pair, one line in registry.cpp and
// one CMake line.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "algorithms/estimate.h"
#include "algorithms/cloud/filters.h"
#include "algorithms/point_cloud.h"
#include "synth/registry.h"

namespace grapebench {

// A created estimator: what it reports (rows even when it fails) and the bound run.
// `input`: what it measures, so a scene pairs it with a protocol that gives it:
// "cloud" (multi_view, single_frame), "stereo_pair", "labelled_cloud" (classification),
// "image" (detection: a colour image, its right image too when the sensor gives one), or
// "any" (an external program).
struct EstimatorBinding {
  std::vector<Quantity> quantities;
  BoundEstimator run;
  std::string input = "cloud";
};
const Registry<EstimatorBinding>& estimator_registry();

// Pipeline steps on a point cloud (scene `pipeline.view_filters` / `cloud_filters`).
using BoundFilter = std::function<FilteredCloud(const PointCloud& cloud)>;
const Registry<BoundFilter>& filter_registry();

}  // namespace grapebench
