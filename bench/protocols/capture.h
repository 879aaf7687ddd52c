// The stage every protocol starts with: the bunch from its seed, its exact ground
// truth, the ray scene (with foliage when the scene has it) and the scan of the rig.
#pragma once

#include <functional>

#include "bench/case_result.h"
#include "bench/scene.h"
#include "sensors/scan.h"
#include "synth/ground_truth.h"

namespace grapebench {

struct CaseCapture {
  Bunch bunch;
  GroundTruth truth;
  RayScene rays;
  Scan scan;
};

// Throws InputError when the scene has no sensor or rig. The scan draws from the same
// stream as `grapebench scan`, so a case's scan can be written and inspected.
CaseCapture capture_case(const Scene& scene, const BunchJob& job);

// A case of a protocol that measures each view alone: the capture (timed), then
// `measure`; what either throws becomes the case's error.
CaseResult measure_views(const Condition& condition, int condition_index, const BunchJob& job,
                         const std::function<void(const CaseCapture&, CaseResult&)>& measure);

}  // namespace grapebench
