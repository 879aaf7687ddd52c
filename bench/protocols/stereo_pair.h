// The stereo_pair protocol (seed 001): every station of the rig is one rectified colour
// stereo pair, measured alone. Named stages: scan (capture.h), then per pair the
// estimator input (the pair and its camera), the exact truth of the pair (peduncle
// pixels, the cluster's pixels, projected berries, the peduncle's axis), the estimators,
// and the scoring of each output kind: the cutting point (a point), the berries
// (detections), the cluster region (a "bunch" instance) and the bounding volume
// (scalars).
#pragma once

#include "bench/case_result.h"
#include "bench/scoring/detections.h"
#include "sensors/scan.h"

namespace grapebench {

// The rectified pair of a stereo frame; pixel centres move to OpenCV's convention.
// Throws InputError when the frame has no colour pair (a depth sensor).
EstimatorInput stereo_input(const ScanView& view);

// What a pair is scored against, all from the exact ray scene of the left camera.
// The stalk is where a cut severs the whole cluster: the peduncle and the bare top of
// the rachis above its first branch (the synthetic bunch's peduncle meets the rachis
// at its top; the paper's "peduncle" is all the stalk above the cluster).
struct StereoTruth {
  int width = 0, height = 0;
  std::vector<std::uint8_t> stalk;   // H x W: 1 where the left label image sees the stalk
  std::vector<std::uint8_t> cluster; // H x W: 1 on the cluster below the stalk (berries, pedicels, branches)
  int berry_top = -1;                // topmost row a berry is seen in, px (-1: none)
  std::vector<TruthObject> berries;  // projected true berries (OpenCV pixels), visible per the fraction
  // The stalk's axis: peduncle and bare rachis, as segments in the left camera frame, m.
  std::vector<std::pair<Vec3, Vec3>> stalk_axis;
};
// World height (z, m) of the highest branch on the rachis: a cut above it severs the
// whole cluster.
double first_branch_height(const Bunch& bunch);
StereoTruth stereo_truth(const ScanView& view, const Bunch& bunch, double visible_fraction);

// Rows of the cutting point: cut_success (1 when the pixel lies within `tolerance` px
// of a stalk pixel; 0 when missed or not found), cut_z and cut_x (the 3D point against
// the exact surface point behind the detected pixel: seed 001 Eqs. 10-11),
// cut_axis_distance (from the stalk's axis: what a gripper needs).
std::vector<EstimateRow> cutting_point_rows(const EstimateRow& base, const Estimate& e, const ScanView& view,
                                            const StereoTruth& truth, double tolerance);
// Rows of the berry circles: berries_found (estimate: visible berries matched; truth:
// visible berries; seed 001 Table 1), berry_precision, berry_centre_error (px, mean
// over the matched) and berry_radius_error (px, signed mean, detection - truth).
std::vector<EstimateRow> berry_rows(const EstimateRow& base, const Estimate& e, const StereoTruth& truth);

// Rows of the cluster region an estimator stands on: its best-scored "bunch" instance,
// read as the detection protocol reads answers (mask, COCO RLE, or a box's pixels);
// no rows when it answers none. cluster_iou (against the truth's cluster pixels) and
// cluster_top_px (its top row; truth: the topmost berry row; negative error: the region
// reaches above the berries, where the cutting point's ROI is placed). A malformed
// answer fails both rows with the reason (the case's other rows stand).
std::vector<EstimateRow> cluster_rows(const EstimateRow& base, const Estimate& e, const StereoTruth& truth);

// The oracle ablation's inputs from the exact truth (pipeline.oracle; null for none):
// the truth's cluster pixels, and the left view redrawn from the label image with
// each berry's pixels white (255) and black where a 4-neighbour is not the same
// berry, everything else black: the outlines the berry stage's Hough circles read.
std::shared_ptr<const StereoOracle> stereo_oracle(PipelineSpec::Oracle oracle, const ScanView& view,
                                                  const StereoTruth& truth);

// Every estimator on view k's pair; appends its rows to r.rows.
void measure_pair(const Scene& scene, const ScanView& view, std::size_t k, const Bunch& bunch, const GroundTruth& gt,
                  CaseResult& r);

CaseResult run_stereo_pair(const Condition& condition, int condition_index, const BunchJob& job);
// The same for one bunch under conditions that differ only in the sensor's light
// (renderer ray): each pair rendered once for all the lights (ProtocolRun::run_together).
std::vector<CaseResult> run_stereo_pair_together(std::span<const Condition* const> conditions,
                                                 std::span<const int> condition_indices, const BunchJob& job);

}  // namespace grapebench
