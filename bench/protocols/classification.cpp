#include "bench/protocols/classification.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>

#include "bench/protocols/capture.h"
#include "bench/protocols/stereo_pair.h"
#include "bench/scoring/classes.h"
#include "bench/scoring/images.h"
#include "bench/scoring/statistics.h"
#include "sensors/mvs_reconstruction.h"
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

namespace {

// The view's colour image: the rendered left image, or the returns' colours (black
// where no ray returned).
RgbImage view_image(const ScanView& v) {
  const OrganisedCloud& c = v.cloud;
  RgbImage im{c.width, c.height, c.left_image};
  if (!im.data.empty()) return im;
  im.data.assign(c.size() * 3, 0);
  for (std::size_t i = 0; i < c.size(); ++i) {
    if (!c.valid[i]) continue;
    for (std::size_t ch = 0; ch < 3; ++ch) im.data[3 * i + ch] = c.rgb[i][ch];
  }
  return im;
}

double rotation_angle_deg(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) {
  return Eigen::AngleAxisd(a.transpose() * b).angle() * 180 / M_PI;
}

// COLMAP's poses in the true frame by a similarity fit: the rotation from the cameras'
// orientations (chordal mean of R_true R_colmap^T; the centres of a straight pass are
// collinear and leave the roll about the line free), then scale and shift by least
// squares on the centres. Views it did not register keep no pose (their points are
// dropped).
std::vector<std::optional<Eigen::Isometry3d>> colmap_poses(const PipelineSpec& pl, const Scan& scan,
                                                           std::uint64_t seed, CaseResult& r) {
  std::vector<RgbImage> images;
  for (const ScanView& v : scan.views) images.push_back(view_image(v));
  const Intrinsics& k = scan.views.front().camera.K;
  // COLMAP centres the top-left pixel at (0.5, 0.5), as this project's cameras do.
  const ColmapPoses c = colmap_sfm(images, k.fx, k.fy, k.cx, k.cy, pl.colmap, seed);
  r.views_registered = c.registered;
  if (c.registered < 3) throw InputError("colmap registered " + std::to_string(c.registered) + " of " +
                                         std::to_string(scan.views.size()) + " views; a similarity fit needs 3");
  Eigen::Matrix3Xd from(3, c.registered), to(3, c.registered);
  Eigen::Matrix3d sum = Eigen::Matrix3d::Zero();
  int n = 0;
  for (std::size_t i = 0; i < c.poses.size(); ++i) {
    if (!c.poses[i]) continue;
    from.col(n) = c.poses[i]->translation(), to.col(n) = scan.views[i].camera.centre(), ++n;
    sum += scan.views[i].camera.pose.linear() * c.poses[i]->linear().transpose();
  }
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(sum, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d rot = svd.matrixU() * svd.matrixV().transpose();
  if (rot.determinant() < 0) rot = svd.matrixU() * Eigen::Vector3d(1, 1, -1).asDiagonal() * svd.matrixV().transpose();
  const Eigen::Matrix3Xd turned = rot * from;
  const Eigen::Vector3d mf = turned.rowwise().mean(), mt = to.rowwise().mean();
  const double spread = (turned.colwise() - mf).squaredNorm();
  if (!(spread > 0)) throw InputError("colmap placed every registered view at one point");
  const double scale = ((turned.colwise() - mf).cwiseProduct(to.colwise() - mt)).sum() / spread;
  if (!(scale > 0)) throw InputError("colmap's camera path runs against the true one (negative scale)");
  Eigen::Matrix4d sim = Eigen::Matrix4d::Identity();
  sim.block<3, 3>(0, 0) = scale * rot;
  sim.block<3, 1>(0, 3) = mt - scale * mf;
  std::vector<std::optional<Eigen::Isometry3d>> out(c.poses.size());
  double rot_sum = 0, rot_max = 0, tr_sum = 0, tr_max = 0;
  for (std::size_t i = 0; i < c.poses.size(); ++i) {
    if (!c.poses[i]) continue;
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.linear() = rot * c.poses[i]->linear();
    pose.translation() = (sim * c.poses[i]->translation().homogeneous()).head<3>();
    const double dr = rotation_angle_deg(pose.linear(), scan.views[i].camera.pose.linear());
    const double dt = (pose.translation() - scan.views[i].camera.centre()).norm() * 1e3;
    rot_sum += dr, rot_max = std::max(rot_max, dr), tr_sum += dt, tr_max = std::max(tr_max, dt);
    out[i] = pose;
  }
  r.rotation_error_mean_deg = rot_sum / n, r.rotation_error_max_deg = rot_max;
  r.translation_error_mean_mm = tr_sum / n, r.translation_error_max_mm = tr_max;
  return out;
}

}  // namespace

std::vector<Eigen::Isometry3d> perturbed_poses(const PipelineSpec& pl, const Scan& scan, std::uint64_t seed,
                                               CaseResult& r) {
  std::vector<Eigen::Isometry3d> poses;
  Rng rng(derive_seed(seed, 0x9053));
  double rot_sum = 0, rot_max = 0, tr_sum = 0, tr_max = 0;
  for (const ScanView& v : scan.views) {
    // One draw per statement, z first (the order GCC gave a call's unspecified
    // argument order; clang reverses it).
    const double az = rng.normal(), ay = rng.normal(), ax = rng.normal();
    const Vec3 axis = Vec3(ax, ay, az).normalized();
    const double angle = pl.pose_rotation_sd * M_PI / 180 * rng.normal();
    const double sz = rng.normal(), sy = rng.normal(), sx = rng.normal();
    const Vec3 shift = pl.pose_translation_sd * Vec3(sx, sy, sz);
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

// SGBM's errors against the exact depths of the pixels it matched, over the views:
// spread and outliers (the noise model's sigma_d and mismatches), how they correlate
// along rows, the fattening behind depth edges, and each plant class's coverage; and
// the left images' pixel noise per plant class (what SGBM matched through).
struct SgbmErrors {
  PixelNoise noise;
  std::vector<double> abs_error;  // px of disparity, per matched pixel with a true depth
  LagCorrelation correlation{{1, 2, 4, 8}};
  long behind_edges = 0, fattened = 0;  // matched pixels just behind an edge; of them, off > 3 px toward the camera
  std::array<double, 3> seen{}, matched{};  // per plant class: pixels seeing it; of them, matched
  double lock_es = 0, lock_ss = 0;          // sums of e s and s^2, s = -sin(2 pi delta), matches within 1 px
  std::array<double, 3> bias_sum{}, bias_count{};  // per plant class, matches within 3 px

  // fb: focal length (px) x baseline (m); block: SGBM's block size (px).
  void add_view(const OrganisedCloud& cloud, const RgbImage& left, const SgbmCloud& c, double fb, int block) {
    std::vector<int> cls(cloud.size());  // each pixel's plant class, -1 none
    for (std::size_t px = 0; px < cloud.size(); ++px) cls[px] = plant_class(static_cast<Part>(cloud.label[px]));
    if (static_cast<std::size_t>(left.width) * left.height == cloud.size())
      noise.add(pixel_noise(left.data, cls, left.width, left.height, 3));
    std::vector<float> signed_error(cloud.size(), std::numeric_limits<float>::quiet_NaN());  // px, matches within 3 px
    // Pixels up to half a block behind a surface >= 3 % nearer: where fattening strikes.
    const std::vector<float> nearer = nearest_depth_within(cloud, block / 2);
    std::vector<char> has_match(cloud.size(), 0);
    for (Eigen::Index i = 0; i < c.points.rows(); ++i) {
      const std::uint32_t pixel = c.pixel[static_cast<std::size_t>(i)];
      has_match[pixel] = 1;
      const double z = c.points(i, 2), truth = cloud.truth(pixel);
      if (!(truth > 0)) continue;
      abs_error.push_back(std::abs(z - truth) * fb / (z * z));
      const double e = fb / z - fb / truth;  // estimated minus true disparity
      if (std::abs(e) <= 3) {
        signed_error[pixel] = static_cast<float>(e);
        if (const int k = cls[pixel]; k >= 0)
          bias_sum[static_cast<std::size_t>(k)] += e, bias_count[static_cast<std::size_t>(k)] += 1;
      }
      if (std::abs(e) <= 1) {
        const double d = fb / truth, s = -std::sin(2 * M_PI * (d - std::floor(d)));
        lock_es += e * s, lock_ss += s * s;
      }
      if (!nearer.empty() && nearer[pixel] < kBehindEdgeDepthRatio * truth) ++behind_edges, fattened += e > 3;
    }
    correlation.add(signed_error, cloud.width, cloud.height);
    for (std::size_t px = 0; px < cloud.size(); ++px)
      if (cls[px] >= 0) seen[static_cast<std::size_t>(cls[px])] += 1, matched[static_cast<std::size_t>(cls[px])] += has_match[px];
  }

  void write(CaseResult& r) {
    if (abs_error.empty()) return;
    const auto off = std::count_if(abs_error.begin(), abs_error.end(), [](double e) { return e > 3; });
    r.disparity_outliers = static_cast<double>(off) / static_cast<double>(abs_error.size());
    auto mid = abs_error.begin() + static_cast<std::ptrdiff_t>(abs_error.size() / 2);
    std::nth_element(abs_error.begin(), mid, abs_error.end());
    r.disparity_error_px = 1.4826 * *mid;
    r.disparity_error_correlation = correlation.correlations();
    r.disparity_fattening = behind_edges > 0 ? static_cast<double>(fattened) / static_cast<double>(behind_edges) : 0;
    for (std::size_t k = 0; k < 3; ++k) r.matched_fraction.push_back(seen[k] > 0 ? matched[k] / seen[k] : 0);
    if (lock_ss > 0) r.disparity_locking = lock_es / lock_ss;
    for (std::size_t k = 0; k < 3; ++k) r.disparity_bias.push_back(bias_count[k] > 0 ? bias_sum[k] / bias_count[k] : 0);
    for (std::size_t k = 0; k < 3; ++k)
      for (const double sd : noise.sd(k)) r.pixel_noise_dn.push_back(sd);
  }
};

FusedCloud reconstruct(const PipelineSpec& pl, const Scan& scan, std::uint64_t seed, CaseResult& r) {
  std::vector<Eigen::Isometry3d> poses = perturbed_poses(pl, scan, seed, r);
  std::vector<bool> placed(scan.views.size(), true);
  if (pl.poses == PipelineSpec::Poses::Colmap) {
    const auto estimated = colmap_poses(pl, scan, seed, r);
    for (std::size_t k = 0; k < poses.size(); ++k) {
      placed[k] = estimated[k].has_value();
      if (placed[k]) poses[k] = *estimated[k];
    }
  }
  if (pl.reconstruction == PipelineSpec::Reconstruction::NoiseModel) {
    r.disparity_error_px = pl.noise_model.disparity_sd;
    r.disparity_outliers = 0;
    if (std::find(placed.begin(), placed.end(), false) == placed.end())
      return mvs_reconstruction(scan, pl.noise_model, pl.fusion, seed, poses);
    Scan kept;  // only the views COLMAP placed
    std::vector<Eigen::Isometry3d> kept_poses;
    for (std::size_t k = 0; k < poses.size(); ++k) {
      if (placed[k]) kept.views.push_back(scan.views[k]), kept_poses.push_back(poses[k]);
    }
    return mvs_reconstruction(kept, pl.noise_model, pl.fusion, seed, kept_poses);
  }
  std::vector<LabelledReturn> returns;
  SgbmErrors errors;
  for (std::size_t k = 0; k < scan.views.size(); ++k) {
    const ScanView& view = scan.views[k];
    if (!placed[k]) continue;
    const EstimatorInput in = stereo_input(view);  // throws unless the sensor renders a colour pair
    const SgbmCloud c = sgbm_reconstruction(*in.stereo, pl.sgbm);
    for (Eigen::Index i = 0; i < c.points.rows(); ++i) {
      // The exact label of the left pixel the point came from (its depth may be wrong).
      const auto part = static_cast<Part>(view.cloud.label[c.pixel[static_cast<std::size_t>(i)]]);
      returns.push_back({poses[k] * Vec3(c.points.row(i).transpose()), c.colours[static_cast<std::size_t>(i)],
                         part, static_cast<int>(k), 0.0});
    }
    errors.add_view(view.cloud, in.stereo->left, c, in.stereo->fx * in.stereo->baseline, pl.sgbm.block_size);
  }
  errors.write(r);
  return fuse_returns(returns, pl.fusion);
}

CaseResult run_classification(const Condition& condition, int condition_index, const BunchJob& job) {
  const Scene& scene = condition.scene;
  return guarded_case(condition, condition_index, job, [&](CaseResult& r) {
    if (!scene.sensor || !scene.rig) throw InputError(scene.path + ": a run needs `sensor:` and `rig:` sections");
    auto t0 = std::chrono::steady_clock::now();
    const RayScene rays = build_row(scene, job);
    const Scan scan = scan_bunch(rays, *scene.sensor, *scene.rig, scene.background, scan_seed(job));
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
  });
}

}  // namespace grapebench
