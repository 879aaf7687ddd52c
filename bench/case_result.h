// What one case of a run produces (rows of estimates beside their truths, pipeline
// scores, timings), its key and case file, and the estimator runs every protocol shares.
#pragma once

#include <array>

#include <chrono>
#include <limits>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "bench/scene.h"
#include "bench/scoring/coco_eval.h"
#include "synth/ground_truth.h"

namespace grapebench {

// One estimated quantity beside its truth. SI units (m3, m).
struct EstimateRow {
  std::string estimator;  // the scene's name for it
  std::string type;
  std::string quantity;  // volume | height | length | width
  bool ok = false;       // false: the estimator failed (error says why)
  double estimate = 0;
  double truth = 0;
  bool watertight = false;
  std::string error;
  std::string notes;         // the estimator's diagnostics (points used, iterations, residuals)
  double seconds = 0;        // wall time of the estimator (not deterministic)
  double peak_heap_mb = -1;  // most heap (every malloc-family call, bench/heap_meter.h) it held above its start, MB; -1: not measured
  // Single-frame pipelines (seed 003): the view, the ROI kind (auto_r, auto_cm,
  // manual_r, manual_cm) and the region's index in that frame; stereo_pair (seed 001):
  // the view and its station's name ("station_0800mm"); -1 / "" otherwise.
  int frame = -1;
  std::string roi;
  int region = -1;
  std::size_t region_points = 0;  // points the estimator saw
  double region_precision = -1;   // fraction of them on the bunch (labels); -1: n/a
};

// A one-vs-rest ROC curve of a classification estimator on the case's test points,
// sampled on the fixed false-positive grid 0, 0.01, ..., 1 (kRocGrid points): the best
// true-positive rate reached at or below each (so curves of cases can be averaged).
inline constexpr int kRocGrid = 101;
struct RocSamples {
  std::string estimator, class_name;
  std::vector<double> tpr;  // kRocGrid values
};

// The confusion matrix of a classification estimator on the case's test points.
struct ConfusionCounts {
  std::string estimator;
  std::vector<std::string> classes;  // K
  std::vector<long long> counts;     // K x K, row-major: rows true class, columns predicted
};

// protocol detection: one view's exact instances and every estimator's answers, kept
// whole because COCO's AP pools the detections of every image (bench/outputs.cpp).
struct DetectionView {
  int view = 0;
  std::string station;        // the rig's name of the view
  int width = 0, height = 0;  // px
  std::vector<CocoObject> truth;  // visible masks; category ids of kDatasetCategories; ids 1..
  // Per estimator (its scene name) that answered: its instances, masks and areas set
  // (a box-only answer as its box's pixels); ids 1.. in answer order.
  std::vector<std::pair<std::string, std::vector<CocoObject>>> answers;
};

inline constexpr std::size_t kPreviewPoints = 6000;

struct CaseResult {
  int condition = 0;
  int bunch = 0;
  std::string preset;
  std::uint64_t seed = 0;
  std::string key;  // hash of everything the case depends on (resume check)
  std::string build;  // build_identity() of the binary that computed it (resume check)
  // The registered cloud of the run's first case (condition 0, bunch 0), at most
  // kPreviewPoints of it (an even stride), for the report's pictures: N x 3, mm.
  std::vector<std::array<float, 3>> preview_points;
  bool ok = false;  // false: the scan or registration failed (error says why)
  std::string error;
  std::size_t points = 0;  // bunch points after segmentation and registration
  int views = 0;
  // Registration against the true relative poses (0 with true_poses).
  double rotation_error_mean_deg = 0, rotation_error_max_deg = 0;
  double translation_error_mean_mm = 0, translation_error_max_mm = 0;
  // Segmentation and view filters against the scan's labels, over all views:
  // precision = bunch points kept / points kept; recall = bunch points kept / bunch
  // returns. 1 and 1 for label segmentation without filters.
  double segmentation_precision = 0, segmentation_recall = 0;
  // Cloud filters: fraction of the peduncle points and of the other bunch points of
  // the registered cloud they keep (0 and 0 without cloud filters).
  double peduncle_kept = 0, body_kept = 0;
  std::vector<EstimateRow> rows;
  std::vector<RocSamples> roc;  // classification: per estimator and class
  std::vector<ConfusionCounts> confusion;  // classification: per estimator
  std::vector<DetectionView> detection;    // detection: per view
  // classification: the reconstruction's disparity error as the noise model's sigma_d
  // (px): 1.4826 x median |z - z_true| f b / z^2 over the matched pixels (sgbm), or the
  // model's own sd (noise_model); -1 for other protocols.
  double disparity_error_px = -1;
  double disparity_outliers = -1;  // fraction of matched pixels off by more than 3 px (sgbm; 0 for the model)
  // classification, sgbm: Pearson's r of the signed disparity errors (matches within
  // 3 px) of pixels 1, 2, 4 and 8 px apart along a row, pooled over the views; empty
  // otherwise.
  std::vector<double> disparity_error_correlation;
  // classification, sgbm: of the matched pixels within half a block behind a surface
  // >= 3 % nearer, the fraction off by more than 3 px toward the camera (foreground
  // fattening); -1 otherwise.
  double disparity_fattening = -1;
  // classification, sgbm: per plant class (berry, branch, leaf), the fraction of the
  // views' pixels seeing it that SGBM matched (after its left-right check); empty otherwise.
  std::vector<double> matched_fraction;
  // classification, sgbm: pixel locking, the amplitude A (px) of the least-squares fit
  // e = -A sin(2 pi delta) of the matches within 1 px, delta the true disparity's
  // fractional part (the noise model's pixel_locking_px); NaN otherwise.
  double disparity_locking = std::numeric_limits<double>::quiet_NaN();
  // classification, sgbm: the left images' pixel noise per plant class (berry, branch,
  // leaf) and channel (R, G, B), 9 values, DN: the sd about the 3 x 3 median over the
  // class's inner pixels, pooled over the views (bench/scoring/images.h); NaN where a
  // class has no inner pixel; empty otherwise.
  std::vector<double> pixel_noise_dn;
  // classification, sgbm: per plant class, the mean signed disparity error (px,
  // estimated minus true: > 0 nearer) of the matches within 3 px; empty otherwise.
  std::vector<double> disparity_bias;
  int views_registered = -1;  // classification with poses: colmap: views the SfM placed
  // Not deterministic:
  double scan_seconds = 0, segmentation_seconds = 0, registration_seconds = 0, filter_seconds = 0;
};

// Everything a case depends on, hashed: the condition's full parameters, the bunch
// job and the program's format version.
std::string case_key(const Condition& condition, const BunchJob& job);

// Runs pipeline steps in order on a cloud and a per-point value carried along (labels,
// pixel indices): each step says which input point every output point comes from.
template <class T>
void apply_filters(const std::vector<FilterSpec>& steps, PointCloud& cloud, std::vector<T>& carried) {
  for (const auto& f : steps) {
    if (cloud.rows() == 0) return;
    FilteredCloud out = f.run(cloud);
    std::vector<T> next(out.source.size());
    for (std::size_t i = 0; i < next.size(); ++i) next[i] = carried[static_cast<std::size_t>(out.source[i])];
    cloud = std::move(out.points);
    carried = std::move(next);
  }
}

// One estimator's answer on one input: its Estimate, or the error it threw; wall time
// and peak heap.
struct TimedEstimate {
  Estimate estimate;
  std::string error;
  double seconds = 0;
  double peak_heap_mb = -1;
};
TimedEstimate run_estimator(const EstimatorSpec& spec, const EstimatorInput& input);
// A row of the estimator's name, type, timing, error and notes (no quantity yet).
EstimateRow estimate_row(const EstimatorSpec& spec, const TimedEstimate& t);
// A row per quantity the estimator reports, beside its truth.
std::vector<EstimateRow> scalar_rows(const EstimatorSpec& spec, const TimedEstimate& t, const GroundTruth& gt,
                                     std::size_t input_points);

// The rows of every estimator of `specs` on what the protocol hands over, timed, with
// their truths; when `cloud_error` is set the cloud could not be made and every row
// fails with it.
std::vector<EstimateRow> run_estimators(const std::vector<EstimatorSpec>& specs, const EstimatorInput& input,
                                        const GroundTruth& gt, const std::string& cloud_error);

// A case's identity (condition, bunch, preset, seed, key), before any stage ran.
CaseResult new_case(const Condition& condition, int condition_index, const BunchJob& job);

// The case file's content; its last field `digest` is case_digest() of the rest.
nlohmann::ordered_json case_to_json(const CaseResult& c);
// FNV-1a (64 bits) of the file's content without `digest`, keys sorted. It finds
// edits and damage, not a forger who recomputes it: external programs are kept from
// the output folder by their sandbox (synth/confined_program.h).
std::string case_digest(const nlohmann::json& j);
struct CaseDigestMismatch : std::runtime_error {
  CaseDigestMismatch() : std::runtime_error("the case file does not match its digest (edited or damaged)") {}
};
// Throws CaseDigestMismatch when the content does not match its digest, and
// std::exception when the file is of another format or a field is missing, of the
// wrong type or out of range.
CaseResult case_from_json(const nlohmann::json& j);

double seconds_since(std::chrono::steady_clock::time_point t0);

}  // namespace grapebench
