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

// The colour image of a view as image estimators get it: the left image, the right one
// when the sensor rendered it (with the baseline), the camera (OpenCV pixel centres).
// Throws InputError without a colour image (a depth sensor).
EstimatorInput image_input(const ScanView& view);

// A new case with `body` run on it: ok when the body returns, failed with what it
// threw (a case's error never escapes its protocol; the run goes on with the next).
CaseResult guarded_case(const Condition& condition, int condition_index, const BunchJob& job,
                        const std::function<void(CaseResult&)>& body);

// A case of a protocol that measures each view alone: the bunch, its truth and ray
// scene, then each view measured as soon as it is captured (`measure`, view k), so a
// pass of a thousand frames holds one; `finish` after the last. What any of them
// throws becomes the case's error. scan_seconds times the bunch and the captures.
using ViewMeasure = std::function<void(const Bunch&, const GroundTruth&, const ScanView&, std::size_t k, CaseResult&)>;
CaseResult measure_views(const Condition& condition, int condition_index, const BunchJob& job,
                         const ViewMeasure& measure, const std::function<void(CaseResult&)>& finish = {});

}  // namespace grapebench
