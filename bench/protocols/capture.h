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
// The seed of a case's scan: view k draws from view_seed(scan_seed(job), k).
std::uint64_t scan_seed(const BunchJob& job);

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
// The one-condition case of measure_views_together.
using ViewMeasure = std::function<void(const Bunch&, const GroundTruth&, const ScanView&, std::size_t k, CaseResult&)>;
CaseResult measure_views(const Condition& condition, int condition_index, const BunchJob& job,
                         const ViewMeasure& measure, const std::function<void(CaseResult&)>& finish = {});
// The same for one bunch under several conditions at once (protocols' CasesRun): the
// bunch, truth and ray scene once (the first condition's scene: they differ in their
// sensors alone), each view captured once for all (scan_views_together) and measured
// per condition (`measure`, condition c of the span). A failed capture fails every
// case; a measure that throws fails its own and the others go on; once every case
// failed, no further view is captured. scan_seconds: the
// bunch's and the captures' time over the conditions' count.
using ViewsMeasure = std::function<void(std::size_t c, const Bunch&, const GroundTruth&, const ScanView&, std::size_t k,
                                        CaseResult&)>;
std::vector<CaseResult> measure_views_together(std::span<const Condition* const> conditions,
                                               std::span<const int> condition_indices, const BunchJob& job,
                                               const ViewsMeasure& measure);

}  // namespace grapebench
