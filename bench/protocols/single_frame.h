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
// One view (k) at a time; `tally` carries the segmentation counts to finish_frames,
// which sets the precision and recall. r.points must start at 0.
struct FrameTally {
  std::size_t auto_kept = 0, auto_bunch = 0, frame_bunch = 0;
};
void measure_frame(const Scene& scene, const ScanView& view, std::size_t k, const GroundTruth& gt, FrameTally& tally,
                   CaseResult& r);
void finish_frames(const FrameTally& tally, CaseResult& r);

CaseResult run_single_frame(const Condition& condition, int condition_index, const BunchJob& job);

}  // namespace grapebench
