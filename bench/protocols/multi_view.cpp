#include "bench/protocols/multi_view.h"

#include "algorithms/cloud/registration.h"
#include "bench/case_result.h"
#include "bench/protocols/capture.h"
#include "sensors/visibility_hull.h"
#include "synth/utf8.h"

#include <algorithm>
#include <chrono>
#include <cmath>

namespace grapebench {

namespace {

using Clock = std::chrono::steady_clock;

bool is_bunch(std::uint8_t l) { return l <= static_cast<std::uint8_t>(Part::Peduncle); }

// What each point carries through the steps: its ground-truth label, and the view and
// pixel it came from (for the sensor's colour and normal).
struct PointTag {
  std::uint8_t label = 0;
  std::size_t view = 0, pixel = 0;
};

// Stage "segment": per view, the returns on bunch parts (labels) or every return
// (none), in the camera's frame, through the view filters, with their ground-truth
// labels carried along so every step can be scored.
struct SegmentedViews {
  std::vector<RegistrationView> views;
  std::vector<std::vector<PointTag>> tags;  // per view, per point
  std::size_t kept_bunch = 0;               // bunch points kept over all views
};

SegmentedViews segment(const PipelineSpec& pl, const Scan& scan, CaseResult& r) {
  SegmentedViews out;
  std::size_t bunch_returns = 0, kept = 0;
  for (std::size_t k = 0; k < scan.views.size(); ++k) {
    const ScanView& v = scan.views[k];
    std::vector<Vec3> pts;
    std::vector<PointTag> tags;
    for (std::size_t i = 0; i < v.cloud.size(); ++i) {
      if (!v.cloud.valid[i]) continue;
      bunch_returns += is_bunch(v.cloud.label[i]);
      if (pl.segmentation == PipelineSpec::Segmentation::Labels && !is_bunch(v.cloud.label[i])) continue;
      pts.push_back(v.cloud.xyz[i].cast<double>());
      tags.push_back({v.cloud.label[i], k, i});
    }
    RegistrationView rv;
    rv.points = to_point_cloud(pts);
    apply_filters(pl.view_filters, rv.points, tags);
    for (const auto& t : tags) out.kept_bunch += is_bunch(t.label);
    kept += tags.size();
    rv.name = v.rig.name;
    rv.bottom = v.rig.name == "bottom";
    out.views.push_back(std::move(rv));
    out.tags.push_back(std::move(tags));
  }
  r.segmentation_precision = kept ? static_cast<double>(out.kept_bunch) / static_cast<double>(kept) : 0;
  r.segmentation_recall = bunch_returns ? static_cast<double>(out.kept_bunch) / static_cast<double>(bunch_returns) : 0;
  return out;
}

// Stage "register": each view's pose by the scene's registration method, and the
// pose errors against the truth in `r` where the method estimated them.
std::vector<Eigen::Isometry3d> register_views(const PipelineSpec& pl, const Scan& scan, const GroundTruth& gt,
                                              const BunchJob& job, std::vector<RegistrationView>& views,
                                              CaseResult& r) {
  RegistrationContext context;
  for (const auto& v : scan.views) context.rig_poses.push_back(v.rig.pose);
  context.axis_point = 0.5 * (gt.bbox_min + gt.bbox_max);
  context.seed = job.seed;
  if (pl.registration.type != "true_poses") {
    for (const auto& v : views) {
      if (v.points.rows() < 10) {
        throw InputError("view " + v.name + " has " + std::to_string(v.points.rows()) +
                         " bunch points; registration needs at least 10 in every view");
      }
    }
  }
  const RegistrationOutcome reg = pl.registration.run(views, context);
  if (!reg.estimated) return reg.poses;
  const Eigen::Isometry3d t0_inv = scan.views.front().rig.pose.inverse();
  double rsum = 0, tsum = 0;
  for (std::size_t k = 1; k < views.size(); ++k) {
    const Eigen::Isometry3d truth = t0_inv * scan.views[k].rig.pose;
    const double re = rotation_error_deg(reg.poses[k], truth);
    const double te = centroid_displacement(reg.poses[k], truth, views[k].points) * 1e3;
    rsum += re;
    tsum += te;
    r.rotation_error_max_deg = std::max(r.rotation_error_max_deg, re);
    r.translation_error_max_mm = std::max(r.translation_error_max_mm, te);
  }
  if (views.size() > 1) {
    r.rotation_error_mean_deg = rsum / static_cast<double>(views.size() - 1);
    r.translation_error_mean_mm = tsum / static_cast<double>(views.size() - 1);
  }
  return reg.poses;
}

// Stage "merge": every view under its pose, in view order, each point with its label
// and its view (a view's points are in its camera's frame, so the pose carries the
// camera centre to poses[k].translation()).
struct MergedCloud {
  PointCloud points;
  std::vector<PointTag> tags;  // per point
};

MergedCloud merge(const SegmentedViews& s, const std::vector<Eigen::Isometry3d>& poses) {
  std::vector<Vec3> pts;
  MergedCloud m;
  for (std::size_t k = 0; k < s.views.size(); ++k) {
    const PointCloud& p = s.views[k].points;
    for (Eigen::Index i = 0; i < p.rows(); ++i) pts.push_back(poses[k] * p.row(i).transpose());
    m.tags.insert(m.tags.end(), s.tags[k].begin(), s.tags[k].end());
  }
  m.points = to_point_cloud(pts);
  return m;
}

// Stage "filter": the cloud filters (MLS, stalk removal, downsampling...) on the
// registered cloud, scored by the labels they keep.
void filter(const PipelineSpec& pl, std::size_t kept_bunch, MergedCloud& m, CaseResult& r) {
  const auto count = [&](auto pred) {
    return static_cast<double>(
        std::count_if(m.tags.begin(), m.tags.end(), [&](const PointTag& t) { return pred(t.label); }));
  };
  const auto peduncle = [](std::uint8_t l) { return l == static_cast<std::uint8_t>(Part::Peduncle); };
  const double peduncle_before = count(peduncle), body_before = static_cast<double>(kept_bunch) - peduncle_before;
  apply_filters(pl.cloud_filters, m.points, m.tags);
  if (!pl.cloud_filters.empty()) {
    r.peduncle_kept = peduncle_before > 0 ? count(peduncle) / peduncle_before : 0;
    r.body_kept = body_before > 0 ? (count(is_bunch) - count(peduncle)) / body_before : 0;
  }
}

// What the estimators get: the registered cloud, each point's camera centre, the
// sensor's normal (turned into the cloud's frame) and colour, and the views.
EstimatorInput estimator_input(MergedCloud& m, const Scan& scan, const std::vector<Eigen::Isometry3d>& poses,
                               SegmentedViews& s) {
  EstimatorInput in;
  const auto n = static_cast<Eigen::Index>(m.tags.size());
  in.viewpoints.resize(n, 3);
  in.normals.resize(n, 3);
  in.colours.resize(m.tags.size());
  for (Eigen::Index i = 0; i < n; ++i) {
    const PointTag& t = m.tags[static_cast<std::size_t>(i)];
    const OrganisedCloud& c = scan.views[t.view].cloud;
    in.viewpoints.row(i) = poses[t.view].translation().transpose();
    in.normals.row(i) = (poses[t.view].linear() * c.normal[t.pixel].cast<double>()).transpose();
    in.colours[static_cast<std::size_t>(i)] = c.rgb[t.pixel];
  }
  for (std::size_t k = 0; k < s.views.size(); ++k) {
    in.views.push_back({s.views[k].name, poses[k], std::move(s.views[k].points)});
  }
  in.points = std::move(m.points);
  return in;
}

// The rig's visibility hull as a scored volume row: the floor of any estimator that
// invents no geometry (pipeline.visibility_hull).
EstimateRow visibility_floor(const Scene& scene, const CaseCapture& c) {
  EstimateRow row;
  row.estimator = row.type = "visibility_hull";
  row.quantity = quantity_name(Quantity::Volume);
  std::vector<Camera> cameras;
  for (const auto& v : c.scan.views) cameras.push_back(v.camera);
  const auto t0 = Clock::now();
  row.truth = c.truth.volume.solid;
  row.estimate = visibility_hull(c.rays, cameras, {scene.pipeline.visibility_hull, 0.003}).volume;
  row.seconds = seconds_since(t0);
  row.ok = row.watertight = true;
  return row;
}

// At most kPreviewPoints of the cloud at an even stride, mm rounded to 0.1.
std::vector<std::array<float, 3>> preview_of(const PointCloud& points) {
  std::vector<std::array<float, 3>> out;
  const auto n = static_cast<std::size_t>(points.rows());
  const std::size_t stride = std::max<std::size_t>(1, (n + kPreviewPoints - 1) / kPreviewPoints);
  for (std::size_t i = 0; i < n; i += stride) {
    std::array<float, 3> p;
    for (int k = 0; k < 3; ++k) {
      p[static_cast<std::size_t>(k)] = static_cast<float>(std::round(points(static_cast<Eigen::Index>(i), k) * 1e4) / 10);
    }
    out.push_back(p);
  }
  return out;
}

}  // namespace

CaseResult run_multi_view(const Condition& condition, int condition_index, const BunchJob& job) {
  const Scene& scene = condition.scene;
  const PipelineSpec& pl = scene.pipeline;
  CaseResult r = new_case(condition, condition_index, job);
  EstimatorInput input;  // the bunch cloud with its per-point attributes and views
  GroundTruth truth;
  EstimateRow floor;
  floor.estimator = floor.type = "visibility_hull";
  floor.quantity = quantity_name(Quantity::Volume);
  floor.error = "not measured: the case failed first";
  try {
    auto t0 = Clock::now();
    const CaseCapture capture = capture_case(scene, job);
    truth = capture.truth;
    r.scan_seconds = seconds_since(t0);
    r.views = static_cast<int>(capture.scan.views.size());
    if (pl.visibility_hull > 0) floor = visibility_floor(scene, capture);

    t0 = Clock::now();
    SegmentedViews segmented = segment(pl, capture.scan, r);
    r.segmentation_seconds = seconds_since(t0);

    t0 = Clock::now();
    const auto poses = register_views(pl, capture.scan, truth, job, segmented.views, r);
    MergedCloud merged = merge(segmented, poses);
    r.registration_seconds = seconds_since(t0);

    t0 = Clock::now();
    filter(pl, segmented.kept_bunch, merged, r);
    input = estimator_input(merged, capture.scan, poses, segmented);
    r.filter_seconds = seconds_since(t0);
    r.points = static_cast<std::size_t>(input.points.rows());
    if (condition_index == 0 && job.index == 0) r.preview_points = preview_of(input.points);
    if (static_cast<double>(input.points.rows()) < pl.min_points) {
      throw InputError("only " + std::to_string(input.points.rows()) + " bunch points (pipeline.min_points " +
                       std::to_string(static_cast<long long>(pl.min_points)) + ")");
    }
    r.ok = true;
  } catch (const std::exception& e) {
    r.ok = false;
    r.error = escape_invalid_utf8(e.what());
  }
  // Stage "estimate": every estimator on the registered cloud (failed rows when it
  // could not be made), then the rig's floor.
  r.rows = run_estimators(scene.estimators, input, truth, r.ok ? "" : "no cloud: " + r.error);
  if (pl.visibility_hull > 0) r.rows.push_back(floor);
  return r;
}

}  // namespace grapebench
