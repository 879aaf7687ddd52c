#include "bench/protocols/classification.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "bench/protocols/stereo_pair.h"
#include "bench/scoring/classes.h"
#include "synth/generate.h"
#include "synth/rng.h"

namespace grapebench {

const std::vector<std::string>& plant_classes() {
  static const std::vector<std::string> names{"berry", "branch", "leaf"};
  return names;
}

int plant_class(Part part) {
  switch (part) {
    case Part::Berry:
      return 0;
    case Part::Pedicel:
    case Part::Rachis:
    case Part::Peduncle:
    case Part::Cane:
      return 1;
    case Part::Leaf:
      return 2;
    default:
      return -1;
  }
}

std::vector<int> split_row(FusedCloud& cloud, double gap, std::vector<int>& truth) {
  FusedCloud kept;
  kept.returns = cloud.returns;
  std::vector<int> train;
  truth.clear();
  for (std::size_t i = 0; i < cloud.points.size(); ++i) {
    const double x = cloud.points[i].x();
    const int c = plant_class(cloud.labels[i]);
    if (c < 0 || std::abs(x) <= 0.5 * gap) continue;
    kept.points.push_back(cloud.points[i]);
    kept.colours.push_back(cloud.colours[i]);
    kept.labels.push_back(cloud.labels[i]);
    kept.depth_sd.push_back(cloud.depth_sd[i]);
    train.push_back(x < 0 ? c : -1);
    truth.push_back(c);
  }
  cloud = std::move(kept);
  return train;
}

namespace {

EstimateRow rate(const EstimateRow& base, const std::string& quantity, double value) {
  EstimateRow r = base;
  r.quantity = quantity;
  r.estimate = value;
  r.truth = 1;
  r.ok = base.error.empty() && std::isfinite(value);
  if (base.error.empty() && !std::isfinite(value)) r.error = "undefined (no point of the class, or none predicted)";
  return r;
}

}  // namespace

std::vector<double> sample_roc(const RocCurve& curve) {
  std::vector<double> out(kRocGrid, 0.0);
  std::size_t i = 0;
  double best = 0;
  for (int g = 0; g < kRocGrid; ++g) {  // the curve's fpr never decreases
    const double fpr = static_cast<double>(g) / (kRocGrid - 1);
    for (; i < curve.fpr.size() && curve.fpr[i] <= fpr + 1e-12; ++i) best = std::max(best, curve.tpr[i]);
    out[static_cast<std::size_t>(g)] = best;
  }
  return out;
}

std::vector<EstimateRow> classification_rows(const EstimateRow& base, const Estimate& e,
                                             const std::vector<int>& train_labels, const std::vector<int>& truth,
                                             std::vector<RocSamples>* roc, std::vector<ConfusionCounts>* confusion) {
  const std::vector<std::string>& classes = plant_classes();
  const char* kinds[] = {"auc_", "iou_", "precision_", "recall_"};
  std::vector<EstimateRow> rows;
  const auto k = static_cast<Eigen::Index>(classes.size());
  std::string error = base.error;
  if (error.empty() && (e.class_scores.rows() != static_cast<Eigen::Index>(truth.size()) || e.class_scores.cols() != k))
    error = "class scores are " + std::to_string(e.class_scores.rows()) + " x " +
            std::to_string(e.class_scores.cols()) + ", expected " + std::to_string(truth.size()) + " x " +
            std::to_string(k);
  if (error.empty() && !e.class_scores.allFinite()) error = "a class score is not finite";
  if (!error.empty()) {
    EstimateRow failed = base;
    failed.error = error;
    for (const char* q : {"accuracy", "miou", "berry_tpr", "berry_fpr"}) rows.push_back(rate(failed, q, NAN));
    for (const char* kind : kinds)
      for (const auto& c : classes) rows.push_back(rate(failed, kind + c, NAN));
    return rows;
  }
  std::vector<int> test_truth;
  std::vector<Eigen::Index> test;
  for (std::size_t i = 0; i < truth.size(); ++i) {
    if (train_labels[i] >= 0) continue;
    test.push_back(static_cast<Eigen::Index>(i));
    test_truth.push_back(truth[i]);
  }
  Eigen::MatrixXd scores(static_cast<Eigen::Index>(test.size()), k);
  for (std::size_t i = 0; i < test.size(); ++i) scores.row(static_cast<Eigen::Index>(i)) = e.class_scores.row(test[i]);
  const ClassScores s = score_classes(test_truth, scores, classes);
  EstimateRow b = base;
  b.region_points = test.size();
  rows.push_back(rate(b, "accuracy", s.accuracy));
  rows.push_back(rate(b, "miou", s.miou));
  // The berry class's operating point: TP rate and FP rate of the argmax labels.
  const double positives = s.confusion.row(0).sum(), negatives = static_cast<double>(s.points) - positives;
  const double false_pos = s.confusion.col(0).sum() - s.confusion(0, 0);
  rows.push_back(rate(b, "berry_tpr", positives > 0 ? s.confusion(0, 0) / positives : NAN));
  rows.push_back(rate(b, "berry_fpr", negatives > 0 ? false_pos / negatives : NAN));
  for (std::size_t c = 0; c < classes.size(); ++c) rows.push_back(rate(b, "auc_" + classes[c], s.auc[c]));
  for (std::size_t c = 0; c < classes.size(); ++c) rows.push_back(rate(b, "iou_" + classes[c], s.iou[c]));
  for (std::size_t c = 0; c < classes.size(); ++c) rows.push_back(rate(b, "precision_" + classes[c], s.precision[c]));
  for (std::size_t c = 0; c < classes.size(); ++c) rows.push_back(rate(b, "recall_" + classes[c], s.recall[c]));
  if (confusion) {
    ConfusionCounts m{base.estimator, classes, {}};
    for (Eigen::Index t = 0; t < k; ++t)
      for (Eigen::Index p = 0; p < k; ++p) m.counts.push_back(s.confusion(t, p));
    confusion->push_back(std::move(m));
  }
  if (roc) {
    for (std::size_t c = 0; c < classes.size(); ++c) roc->push_back({base.estimator, classes[c], sample_roc(s.roc[c])});
  }
  return rows;
}

RayScene build_row(const Scene& scene, const BunchJob& job) {
  const VineRowParams& row = *scene.vine_row;
  std::vector<Bunch> bunches;
  for (std::size_t k = 0; k < vine_row_anchors(row).size(); ++k)
    bunches.push_back(generate_bunch(job.params, derive_seed(job.seed, 0x40000 + k)));
  return scene_rays(scene, vine_row(bunches, row, derive_seed(job.seed, 0x4a1e)), job.seed);
}

std::vector<Eigen::Isometry3d> perturbed_poses(const PipelineSpec& pl, const Scan& scan, std::uint64_t seed,
                                               CaseResult& r) {
  std::vector<Eigen::Isometry3d> poses;
  Rng rng(derive_seed(seed, 0x9053));
  double rot_sum = 0, rot_max = 0, tr_sum = 0, tr_max = 0;
  for (const ScanView& v : scan.views) {
    const Vec3 axis = Vec3(rng.normal(), rng.normal(), rng.normal()).normalized();
    const double angle = pl.pose_rotation_sd * M_PI / 180 * rng.normal();
    const Vec3 shift(pl.pose_translation_sd * rng.normal(), pl.pose_translation_sd * rng.normal(),
                     pl.pose_translation_sd * rng.normal());
    Eigen::Isometry3d pose = v.camera.pose;
    pose.linear() = Eigen::AngleAxisd(angle, axis).toRotationMatrix() * pose.linear();  // about the camera centre
    pose.translation() += shift;
    poses.push_back(pose);
    rot_sum += std::abs(angle) * 180 / M_PI, rot_max = std::max(rot_max, std::abs(angle) * 180 / M_PI);
    tr_sum += shift.norm() * 1e3, tr_max = std::max(tr_max, shift.norm() * 1e3);
  }
  const double n = std::max<double>(1, static_cast<double>(poses.size()));
  r.rotation_error_mean_deg = rot_sum / n, r.rotation_error_max_deg = rot_max;
  r.translation_error_mean_mm = tr_sum / n, r.translation_error_max_mm = tr_max;
  return poses;
}

FusedCloud reconstruct(const PipelineSpec& pl, const Scan& scan, std::uint64_t seed, CaseResult& r) {
  const std::vector<Eigen::Isometry3d> poses = perturbed_poses(pl, scan, seed, r);
  if (pl.reconstruction == PipelineSpec::Reconstruction::NoiseModel) {
    r.disparity_error_px = pl.noise_model.disparity_sd;
    r.disparity_outliers = 0;
    return mvs_reconstruction(scan, pl.noise_model, pl.fusion, seed, poses);
  }
  std::vector<LabelledReturn> returns;
  std::vector<double> disparity_error;  // px, per matched pixel with a true depth
  for (std::size_t k = 0; k < scan.views.size(); ++k) {
    const ScanView& view = scan.views[k];
    const EstimatorInput in = stereo_input(view);  // throws unless the sensor renders a colour pair
    const SgbmCloud c = sgbm_reconstruction(*in.stereo, pl.sgbm);
    for (Eigen::Index i = 0; i < c.points.rows(); ++i) {
      const std::uint32_t pixel = c.pixel[static_cast<std::size_t>(i)];
      // The exact label of the left pixel the point came from (its depth may be wrong).
      const auto part = static_cast<Part>(view.cloud.label[pixel]);
      const double z = c.points(i, 2), truth = view.cloud.truth(pixel);
      if (truth > 0) disparity_error.push_back(std::abs(z - truth) * in.stereo->fx * in.stereo->baseline / (z * z));
      returns.push_back({poses[k] * Vec3(c.points.row(i).transpose()), c.colours[static_cast<std::size_t>(i)],
                         part, static_cast<int>(k), 0.0});
    }
  }
  if (!disparity_error.empty()) {
    const auto off = std::count_if(disparity_error.begin(), disparity_error.end(), [](double e) { return e > 3; });
    r.disparity_outliers = static_cast<double>(off) / static_cast<double>(disparity_error.size());
    auto mid = disparity_error.begin() + static_cast<std::ptrdiff_t>(disparity_error.size() / 2);
    std::nth_element(disparity_error.begin(), mid, disparity_error.end());
    r.disparity_error_px = 1.4826 * *mid;
  }
  return fuse_returns(returns, pl.fusion);
}

CaseResult run_classification(const Condition& condition, int condition_index, const BunchJob& job) {
  CaseResult r = new_case(condition, condition_index, job);
  const Scene& scene = condition.scene;
  try {
    if (!scene.sensor || !scene.rig) throw InputError(scene.path + ": a run needs `sensor:` and `rig:` sections");
    auto t0 = std::chrono::steady_clock::now();
    const RayScene rays = build_row(scene, job);
    const Scan scan = scan_bunch(rays, *scene.sensor, *scene.rig, scene.background, derive_seed(job.seed, 0x5ca9));
    r.scan_seconds = seconds_since(t0);
    r.views = static_cast<int>(scan.views.size());
    t0 = std::chrono::steady_clock::now();
    FusedCloud cloud = reconstruct(scene.pipeline, scan, derive_seed(job.seed, 0x3d5), r);
    std::vector<int> truth;
    EstimatorInput in;
    in.train_labels = split_row(cloud, scene.pipeline.split_gap, truth);
    r.registration_seconds = seconds_since(t0);  // the reconstruction stands where registration does
    r.points = cloud.points.size();
    in.points = to_point_cloud(cloud.points);
    in.colours.assign(cloud.colours.begin(), cloud.colours.end());
    in.classes = plant_classes();
    for (const EstimatorSpec& spec : scene.estimators) {
      const TimedEstimate t = run_estimator(spec, in);
      for (EstimateRow& row : classification_rows(estimate_row(spec, t), t.estimate, in.train_labels, truth, &r.roc,
                                                  &r.confusion))
        r.rows.push_back(std::move(row));
    }
    r.ok = true;
  } catch (const std::exception& e) {
    r.ok = false;
    r.error = e.what();
  }
  return r;
}

}  // namespace grapebench
