// The single_frame protocol (seed 003): every view of a scan is measured alone, as the
// paper does with each RealSense frame. Named stages: scan (capture.h), then per frame
// returns, view filters (the pass-through), ROIs, fine tuning, estimate.
#pragma once

#include "bench/case_result.h"
#include "sensors/scan.h"

namespace grapebench {

// A frame's valid returns (camera frame, m) and the pixel of each, so later steps can
// look up colours and labels.
struct FrameReturns {
  PointCloud cloud;
  std::vector<std::size_t> pixel;
};
FrameReturns frame_returns(const OrganisedCloud& c);

// Per view: the valid returns with their colours, the scene's view_filters (seed 003's
// pass-through), then each ROI kind of pipeline.rois (automatic detection, manual
// label box, each as is or widened about its centre of mass by Eq. 2), the fine-tuning
// step, and every estimator on the tuned region. Appends one row per estimator
// quantity, frame, ROI kind and region to r.rows; r.points counts the filtered returns
// and r.segmentation_precision / recall score the tuned automatic regions against the
// labels.
void measure_frames(const Scene& scene, const Scan& scan, const GroundTruth& gt, CaseResult& r);

CaseResult run_single_frame(const Condition& condition, int condition_index, const BunchJob& job);

}  // namespace grapebench
