// The `classification` protocol (seed 004, Dey et al. 2012): a vine-row section is
// built around the case's bunch seed, a camera pass captures it, the views become one
// coloured cloud with exact labels (sensors/mvs_reconstruction), the row is split into
// a training part and a spatially separate test part, and every estimator scores each
// test point per class (berry, branch, leaf); the scores are rated against the labels.
#pragma once

#include <string>
#include <vector>

#include "bench/case_result.h"
#include "bench/scoring/classes.h"
#include "sensors/mvs_reconstruction.h"

namespace grapebench {

// Seed 004's classes, in score-column order.
const std::vector<std::string>& plant_classes();
// Class index of a surface part: berry 0; pedicel, rachis, peduncle and canes (the
// paper's "branches") 1; leaf 2; -1 for background and no return.
int plant_class(Part part);

// Stage "row": the case's bunches (one per place on the row, each from its own seed)
// hung on one cordon, with the scene's foliage over the whole section.
RayScene build_row(const Scene& scene, const BunchJob& job);

// Stage "reconstruct": the pass's views to one coloured cloud with exact labels (the
// scene's reconstruction), back-projected with each view's pose perturbed by the
// scene's pose errors; the disparity and pose errors go into `r`.
FusedCloud reconstruct(const PipelineSpec& pl, const Scan& scan, std::uint64_t seed, CaseResult& r);

// Stage "split": per point of the fused cloud, its class where it lies in the training
// part (x < -gap / 2), -1 in the test part (x > gap / 2); points in the gap are
// dropped from `cloud` (so no neighbourhood joins the two parts). Returns the labels of
// the kept points in order.
std::vector<int> split_row(FusedCloud& cloud, double gap, std::vector<int>& truth);

// Stage "score": an estimator's rows from its class scores on the test points:
// accuracy, miou, berry_tpr and berry_fpr (the operating point of the argmax labels),
// and per class auc_, iou_, precision_, recall_ (estimate beside a truth of 1).
// `roc` and `confusion` (when given) receive the per-class curves sampled on the
// kRocGrid and the confusion matrix.
std::vector<EstimateRow> classification_rows(const EstimateRow& base, const Estimate& e,
                                             const std::vector<int>& train_labels, const std::vector<int>& truth,
                                             std::vector<RocSamples>* roc = nullptr,
                                             std::vector<ConfusionCounts>* confusion = nullptr);

// The curve's best true-positive rate at or below each false-positive rate of the grid.
std::vector<double> sample_roc(const RocCurve& curve);

CaseResult run_classification(const Condition& condition, int condition_index, const BunchJob& job);

}  // namespace grapebench
