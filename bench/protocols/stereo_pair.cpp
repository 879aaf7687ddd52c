#include "bench/protocols/stereo_pair.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include "bench/instance_mask.h"
#include "bench/protocols/capture.h"
#include "synth/generate.h"

namespace grapebench {

EstimatorInput stereo_input(const ScanView& view) {
  const OrganisedCloud& c = view.cloud;
  if (c.left_image.empty() || c.right_image.empty() || c.baseline <= 0) {
    throw InputError("protocol stereo_pair: the sensor gives no colour stereo pair (use sensor type stereo_rgb)");
  }
  return image_input(view);
}

double first_branch_height(const Bunch& bunch) {
  double z = -std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < bunch.stems.size(); ++i) {
    const Stem& s = bunch.stems[i];
    // A branch of the main rachis: not a pedicel, not on the wing (whose side branches
    // leave it near the peduncle, above the body's first branch), not a bent main axis.
    const bool branch = s.part == Part::Rachis && s.parent >= 0 && bunch.stems[s.parent].part == Part::Rachis &&
                        !on_wing(bunch, static_cast<int>(i)) && static_cast<int>(i) != bunch.bend;
    if (branch) z = std::max(z, s.start.z());
  }
  return z;
}

StereoTruth stereo_truth(const ScanView& view, const Bunch& bunch, double visible_fraction) {
  const OrganisedCloud& c = view.cloud;
  StereoTruth t;
  t.width = c.width, t.height = c.height;
  t.stalk.assign(c.size(), 0);
  t.cluster.assign(c.size(), 0);
  const double branch_z = first_branch_height(bunch);
  std::map<int, int> seen;  // berry id -> unoccluded berry pixels
  for (std::size_t i = 0; i < c.size(); ++i) {
    const auto part = static_cast<Part>(c.label[i]);
    if (part == Part::Peduncle) t.stalk[i] = 1;
    // Rachis surface above the first branch: the bare stalk (branches hang downwards).
    if (part == Part::Rachis && c.valid[i] && (view.camera.pose * c.xyz[i].cast<double>()).z() > branch_z)
      t.stalk[i] = 1;
    t.cluster[i] = (part == Part::Berry || part == Part::Pedicel || part == Part::Rachis) && !t.stalk[i];
    if (part == Part::Berry) {
      ++seen[c.berry[i]];
      if (t.berry_top < 0) t.berry_top = static_cast<int>(i / c.width);
    }
  }
  const Intrinsics& k = view.camera.K;
  for (std::size_t b = 0; b < bunch.berries.size(); ++b) {
    const Vec3 p = view.camera.to_camera(bunch.berries[b].centre);
    if (p.z() <= 0) continue;
    const Circle circle{k.fx * p.x() / p.z() + k.opencv_cx(), k.fy * p.y() / p.z() + k.opencv_cy(),
                        k.fx * bunch.berries[b].radius / p.z()};
    const auto it = seen.find(static_cast<int>(b));
    const int pixels = it == seen.end() ? 0 : it->second;
    if (pixels == 0) continue;  // wholly hidden or off the image: neither found nor a false positive's excuse
    t.berries.push_back({circle, pixels >= visible_fraction * M_PI * circle.r * circle.r});
  }
  const Eigen::Isometry3d to_cam = view.camera.pose.inverse();
  const Stem& peduncle = bunch.stems[static_cast<std::size_t>(bunch.peduncle)];
  t.stalk_axis.emplace_back(to_cam * bunch.top, to_cam * peduncle.end);
  if (std::isfinite(branch_z))
    t.stalk_axis.emplace_back(to_cam * bunch.top, to_cam * Vec3(bunch.top.x(), bunch.top.y(), branch_z));
  return t;
}

namespace {

EstimateRow row_of(const EstimateRow& base, const char* quantity, double estimate, double truth, bool ok,
                   std::string error = {}) {
  EstimateRow r = base;
  r.quantity = quantity;
  r.estimate = estimate;
  r.truth = truth;
  r.ok = ok && std::isfinite(estimate);
  if (!error.empty()) r.error = std::move(error);
  return r;
}

double segment_distance(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 ab = b - a;
  const double len2 = ab.squaredNorm();
  const double s = len2 > 0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (p - (a + s * ab)).norm();
}

bool near_stalk(const StereoTruth& t, double x, double y, double tolerance) {
  const int r = static_cast<int>(std::ceil(tolerance));
  const int u0 = static_cast<int>(std::lround(x)), v0 = static_cast<int>(std::lround(y));
  for (int v = v0 - r; v <= v0 + r; ++v) {
    for (int u = u0 - r; u <= u0 + r; ++u) {
      if (u < 0 || v < 0 || u >= t.width || v >= t.height) continue;
      if ((u - x) * (u - x) + (v - y) * (v - y) > tolerance * tolerance + 0.5) continue;
      if (t.stalk[static_cast<std::size_t>(v) * t.width + u]) return true;
    }
  }
  return false;
}

}  // namespace

std::vector<EstimateRow> cutting_point_rows(const EstimateRow& base, const Estimate& e, const ScanView& view,
                                            const StereoTruth& truth, double tolerance) {
  const auto it =
      std::find_if(e.points.begin(), e.points.end(), [](const auto& p) { return p.first == "cutting_point"; });
  if (!base.error.empty() || it == e.points.end()) {
    const std::string why = !base.error.empty() ? base.error : e.error.empty() ? "no cutting point" : e.error;
    // A missed cutting point counts as a failure in the success rate (seed 001 Table 2).
    return {row_of(base, "cut_success", 0, 1, true, why), row_of(base, "cut_z", 0, 0, false, why),
            row_of(base, "cut_x", 0, 0, false, why), row_of(base, "cut_axis_distance", 0, 0, false, why)};
  }
  const Vec3 p = it->second;
  const Intrinsics& k = view.camera.K;
  // The detected pixel, back from the 3D point (the estimator answers in 3D).
  const double x = k.fx * p.x() / p.z() + k.opencv_cx(), y = k.fy * p.y() / p.z() + k.opencv_cy();
  std::vector<EstimateRow> rows{row_of(base, "cut_success", near_stalk(truth, x, y, tolerance) ? 1 : 0, 1, true)};
  const int u = static_cast<int>(std::lround(x)), v = static_cast<int>(std::lround(y));
  const bool inside = u >= 0 && v >= 0 && u < truth.width && v < truth.height;
  const std::size_t i = inside ? static_cast<std::size_t>(v) * truth.width + u : 0;
  if (inside && view.cloud.valid[i]) {
    const Vec3 s = view.cloud.xyz[i].cast<double>();  // Eqs. 10-11's ground truth: the surface behind the pixel
    rows.push_back(row_of(base, "cut_z", p.z(), s.z(), true));
    rows.push_back(row_of(base, "cut_x", p.x(), s.x(), true));
  } else {
    const std::string why = "no surface behind the detected pixel";
    rows.push_back(row_of(base, "cut_z", p.z(), 0, false, why));
    rows.push_back(row_of(base, "cut_x", p.x(), 0, false, why));
  }
  double axis = std::numeric_limits<double>::infinity();
  for (const auto& [a, b] : truth.stalk_axis) axis = std::min(axis, segment_distance(p, a, b));
  rows.push_back(row_of(base, "cut_axis_distance", axis, 0, true));
  return rows;
}

std::vector<EstimateRow> berry_rows(const EstimateRow& base, const Estimate& e, const StereoTruth& truth) {
  if (!base.error.empty()) {
    return {row_of(base, "berries_found", 0, 0, false), row_of(base, "berry_precision", 0, 1, false),
            row_of(base, "berry_centre_error", 0, 0, false), row_of(base, "berry_radius_error", 0, 0, false)};
  }
  const DetectionScore s = score_detections(e.detections, truth.berries, DetectionMatch{});
  std::vector<EstimateRow> rows;
  rows.push_back(row_of(base, "berries_found", s.visible_found, s.visible, true));
  rows.push_back(
      row_of(base, "berry_precision", s.precision, 1, s.detections > 0, s.detections ? "" : "no berry detected"));
  rows.push_back(
      row_of(base, "berry_centre_error", s.centre_error_mean, 0, s.matched > 0, s.matched ? "" : "no berry matched"));
  rows.push_back(
      row_of(base, "berry_radius_error", s.radius_error_mean, 0, s.matched > 0, s.matched ? "" : "no berry matched"));
  return rows;
}

std::vector<EstimateRow> cluster_rows(const EstimateRow& base, const Estimate& e, const StereoTruth& truth) {
  const ImageDetection* region = nullptr;
  std::size_t index = 0;
  for (std::size_t i = 0; i < e.instances.size(); ++i) {
    const ImageDetection& d = e.instances[i];
    if (d.category == "bunch" && (!region || d.score > region->score)) region = &d, index = i;
  }
  if (!region) return {};
  // Read as the detection protocol reads answers (a mask, COCO RLE or a box's pixels),
  // so an external program's region scores as luo2016_stereo's does.
  Rle mask;
  try {
    mask = instance_mask(*region, truth.width, truth.height, "instance " + std::to_string(index) + " (bunch)");
  } catch (const InputError& err) {  // this estimator's rows fail; the case's others stand
    const std::string why = std::string("the estimator's region: ") + err.what();
    return {row_of(base, "cluster_iou", 0, 1, false, why), row_of(base, "cluster_top_px", 0, 0, false, why)};
  }
  const Rle cluster = rle_encode(truth.cluster.data(), truth.width, truth.height);
  const bool empty = rle_area(mask) == 0, none = rle_area(cluster) == 0;
  const double top = empty ? -1 : rle_box(mask)[1];
  std::vector<EstimateRow> rows;
  rows.push_back(row_of(base, "cluster_iou", rle_iou(mask, cluster), 1, !(empty && none),
                        empty && none ? "neither the region nor the truth has a pixel" : ""));
  rows.push_back(row_of(base, "cluster_top_px", top, truth.berry_top, !empty && truth.berry_top >= 0,
                        empty ? "empty region" : truth.berry_top < 0 ? "no berry in view" : ""));
  return rows;
}

namespace {

// The bounding volume against the other truths the paper's measures suggest: the
// ring (smallest enclosing circle, its manual diameter), the height from the cutting
// point and the envelope (convex hull) volume.
std::vector<EstimateRow> bounding_volume_rows(const EstimatorSpec& spec, const TimedEstimate& t,
                                              const GroundTruth& gt) {
  std::vector<EstimateRow> rows = scalar_rows(spec, t, gt, 0);
  const std::size_t n = rows.size();
  for (std::size_t k = 0; k < n; ++k) {
    EstimateRow extra = rows[k];
    if (rows[k].quantity == "max_diameter") {
      extra.quantity = "ring_diameter", extra.truth = gt.ring_diameter;
    } else if (rows[k].quantity == "hanging_height") {
      extra.quantity = "height_from_cutting_point", extra.truth = gt.height_from_cutting_point;
    } else if (rows[k].quantity == "volume") {
      extra.quantity = "envelope_volume", extra.truth = gt.envelope_volume;
    } else {
      continue;
    }
    rows.push_back(extra);
  }
  return rows;
}

}  // namespace

std::shared_ptr<const StereoOracle> stereo_oracle(PipelineSpec::Oracle oracle, const ScanView& view,
                                                  const StereoTruth& truth) {
  using O = PipelineSpec::Oracle;
  if (oracle == O::None) return nullptr;
  auto o = std::make_shared<StereoOracle>();
  if (oracle == O::Cluster || oracle == O::Both) o->cluster = truth.cluster;
  if (oracle == O::Berries || oracle == O::Both) {
    const OrganisedCloud& c = view.cloud;
    const int w = c.width, h = c.height;
    RgbImage& img = o->berry_edges;
    img.width = w, img.height = h;
    img.data.assign(static_cast<std::size_t>(w) * h * 3, 0);
    const auto berry = [&](int u, int v) {
      const std::size_t i = static_cast<std::size_t>(v) * w + u;
      return static_cast<Part>(c.label[i]) == Part::Berry ? c.berry[i] : -1;
    };
    for (int v = 0; v < h; ++v) {
      for (int u = 0; u < w; ++u) {
        const int id = berry(u, v);
        if (id < 0) continue;
        const bool inside = u > 0 && v > 0 && u + 1 < w && v + 1 < h && berry(u - 1, v) == id &&
                            berry(u + 1, v) == id && berry(u, v - 1) == id && berry(u, v + 1) == id;
        if (inside) std::fill_n(img.data.begin() + 3 * (static_cast<std::size_t>(v) * w + u), 3, 255);
      }
    }
  }
  return o;
}

void measure_pair(const Scene& scene, const ScanView& view, std::size_t k, const Bunch& bunch, const GroundTruth& gt,
                  CaseResult& r) {
  const PipelineSpec& pl = scene.pipeline;
  EstimatorInput in = stereo_input(view);
  in.frame->index = static_cast<int>(k);
  const StereoTruth truth = stereo_truth(view, bunch, pl.berry_visible_fraction);
  in.oracle = stereo_oracle(pl.oracle, view, truth);
  for (const EstimatorSpec& spec : scene.estimators) {
    const TimedEstimate t = run_estimator(spec, in);
    std::vector<EstimateRow> rows = bounding_volume_rows(spec, t, gt);
    const EstimateRow base = estimate_row(spec, t);
    for (EstimateRow& row : cutting_point_rows(base, t.estimate, view, truth, pl.cut_tolerance)) rows.push_back(row);
    for (EstimateRow& row : berry_rows(base, t.estimate, truth)) rows.push_back(row);
    for (EstimateRow& row : cluster_rows(base, t.estimate, truth)) rows.push_back(row);
    for (EstimateRow& row : rows) {
      row.frame = static_cast<int>(k);
      row.roi = view.rig.name;
      if (in.oracle) row.notes = std::string("oracle: ") + pl.oracle_name() + (row.notes.empty() ? "" : "; " + row.notes);
      r.rows.push_back(std::move(row));
    }
  }
}

CaseResult run_stereo_pair(const Condition& condition, int condition_index, const BunchJob& job) {
  return measure_views(condition, condition_index, job,
                       [&](const Bunch& bunch, const GroundTruth& truth, const ScanView& view, std::size_t k,
                           CaseResult& r) { measure_pair(condition.scene, view, k, bunch, truth, r); });
}

std::vector<CaseResult> run_stereo_pair_together(std::span<const Condition* const> conditions,
                                                 std::span<const int> condition_indices, const BunchJob& job) {
  return measure_views_together(conditions, condition_indices, job,
                                [&](std::size_t c, const Bunch& bunch, const GroundTruth& truth, const ScanView& view,
                                    std::size_t k, CaseResult& r) {
                                  measure_pair(conditions[c]->scene, view, k, bunch, truth, r);
                                });
}

}  // namespace grapebench
