#include "bench/case_run.h"

#include "algorithms/registration.h"
#include "bench/frame_run.h"
#include "bench/heap_meter.h"
#include "sensors/scan.h"
#include "sensors/visibility_hull.h"
#include "synth/generate.h"
#include "synth/ground_truth.h"
#include "synth/io.h"
#include "synth/rng.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

namespace grapebench {

namespace {

Eigen::Isometry3d rotation_about_vertical(const Vec3& centre, double angle_rad) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = Eigen::AngleAxisd(angle_rad, Vec3::UnitZ()).toRotationMatrix();
  t.translation() = centre - t.linear() * centre;
  return t;
}

}  // namespace

CaseResult run_case(const Condition& condition, int condition_index, const BunchJob& job) {
  const Scene& scene = condition.scene;
  CaseResult r;
  r.condition = condition_index;
  r.bunch = job.index;
  r.preset = job.preset;
  r.seed = job.seed;
  r.key = case_key(condition, job);
  PointCloud merged, viewpoints;  // the bunch cloud and, per point, its camera centre
  GroundTruth gt;
  EstimateRow floor_row;  // the rig's visibility hull, when the pipeline asks for it
  floor_row.estimator = floor_row.type = "visibility_hull";
  floor_row.quantity = quantity_name(Quantity::Volume);
  floor_row.error = "not measured: the case failed first";
  try {
    if (!scene.sensor || !scene.rig) throw InputError(scene.path + ": a run needs `sensor:` and `rig:` sections");
    auto t0 = std::chrono::steady_clock::now();
    const Bunch bunch = generate_bunch(job.params, job.seed);
    gt = compute_ground_truth(bunch, job.params.density);
    const RayScene rays = scene_rays(scene, bunch, job.seed);
    // Same stream as `grapebench scan`, so a case's scan can be written and inspected.
    const Scan scan = scan_bunch(rays, *scene.sensor, *scene.rig, scene.background, derive_seed(job.seed, 0x5ca9));
    r.scan_seconds = seconds_since(t0);
    r.views = static_cast<int>(scan.views.size());
    if (scene.pipeline.visibility_hull > 0 && scene.pipeline.registration != "single_frame") {
      std::vector<Camera> cameras;
      for (const auto& v : scan.views) cameras.push_back(v.camera);
      t0 = std::chrono::steady_clock::now();
      floor_row.truth = gt.volume.solid;
      floor_row.estimate = visibility_hull(rays, cameras, {scene.pipeline.visibility_hull, 0.003}).volume;
      floor_row.seconds = seconds_since(t0);
      floor_row.ok = true;
      floor_row.watertight = true;
      floor_row.error.clear();
    }
    if (scene.pipeline.registration == "single_frame") {
      measure_frames(scene, scan, gt, r);
      r.ok = true;
      return r;
    }

    // Segmentation: the returns on bunch parts (labels) or every return (none), in
    // each camera's frame, with their ground-truth labels carried along so every
    // pipeline step can be scored.
    const auto& pl = scene.pipeline;
    const auto is_bunch = [](std::uint8_t l) { return l <= static_cast<std::uint8_t>(Part::Peduncle); };
    std::vector<RegistrationView> views;
    std::vector<std::vector<std::uint8_t>> view_labels;
    std::size_t bunch_returns = 0, kept = 0, kept_bunch = 0;
    t0 = std::chrono::steady_clock::now();
    for (const auto& v : scan.views) {
      std::vector<Vec3> pts;
      std::vector<std::uint8_t> labels;
      for (std::size_t i = 0; i < v.cloud.size(); ++i) {
        if (!v.cloud.valid[i]) continue;
        bunch_returns += is_bunch(v.cloud.label[i]);
        if (pl.segmentation == "labels" && !is_bunch(v.cloud.label[i])) continue;
        pts.push_back(v.cloud.xyz[i].cast<double>());
        labels.push_back(v.cloud.label[i]);
      }
      RegistrationView rv;
      rv.points = to_point_cloud(pts);
      apply_filters(pl.view_filters, rv.points, labels);
      for (auto l : labels) kept_bunch += is_bunch(l);
      kept += labels.size();
      rv.name = v.rig.name;
      rv.bottom = v.rig.name == "bottom";
      views.push_back(std::move(rv));
      view_labels.push_back(std::move(labels));
    }
    r.segmentation_precision = kept ? static_cast<double>(kept_bunch) / static_cast<double>(kept) : 0;
    r.segmentation_recall = bunch_returns ? static_cast<double>(kept_bunch) / static_cast<double>(bunch_returns) : 0;
    r.segmentation_seconds = seconds_since(t0);

    const Eigen::Isometry3d t0_inv = scan.views.front().rig.pose.inverse();
    t0 = std::chrono::steady_clock::now();
    std::vector<Eigen::Isometry3d> poses(views.size());
    if (pl.registration == "true_poses") {
      for (std::size_t k = 0; k < views.size(); ++k) poses[k] = scan.views[k].rig.pose;
    } else {
      for (const auto& v : views) {
        if (v.points.rows() < 10) {
          throw InputError("view " + v.name + " has " + std::to_string(v.points.rows()) +
                           " bunch points; registration needs at least 10 in every view");
        }
      }
      RegistrationResult reg;
      if (pl.registration == "seed000_pca_icp") {
        reg = register_seed000(views, pl.icp, pl.group_size);
      } else if (pl.registration == "plain_icp") {
        reg = register_plain_icp(views, pl.icp);
      } else {
        // Known turntable angles about a calibrated axis; an optional seeded angle
        // error stands for the turntable's positioning error.
        const Vec3 centre = 0.5 * (gt.bbox_min + gt.bbox_max);
        Rng rng(derive_seed(job.seed, 0xa11e));
        for (std::size_t k = 1; k < views.size(); ++k) {
          const double err = pl.angle_error_sd_deg * rng.normal() * M_PI / 180;
          views[k].nominal = t0_inv * rotation_about_vertical(centre, err) * scan.views[k].rig.pose;
        }
        const Vec3 up = t0_inv.linear() * Vec3::UnitZ();
        reg = register_known_angle(views, up, pl.icp, pl.bottom_band);
      }
      poses = reg.poses;
      double rsum = 0, tsum = 0;
      for (std::size_t k = 1; k < views.size(); ++k) {
        const Eigen::Isometry3d truth = t0_inv * scan.views[k].rig.pose;
        const double re = rotation_error_deg(reg.poses[k], truth), te = centroid_displacement(reg.poses[k], truth, views[k].points) * 1e3;
        rsum += re;
        tsum += te;
        r.rotation_error_max_deg = std::max(r.rotation_error_max_deg, re);
        r.translation_error_max_mm = std::max(r.translation_error_max_mm, te);
      }
      if (views.size() > 1) {
        r.rotation_error_mean_deg = rsum / static_cast<double>(views.size() - 1);
        r.translation_error_mean_mm = tsum / static_cast<double>(views.size() - 1);
      }
    }
    // The registered cloud: every view under its pose, in view order, with its labels
    // and views (a view's points are in its camera's frame, so the pose carries the
    // camera centre to poses[k].translation()).
    std::vector<Vec3> pts;
    std::vector<std::uint8_t> labels;
    std::vector<std::size_t> seen_by;
    for (std::size_t k = 0; k < views.size(); ++k) {
      for (Eigen::Index i = 0; i < views[k].points.rows(); ++i) pts.push_back(poses[k] * views[k].points.row(i).transpose());
      labels.insert(labels.end(), view_labels[k].begin(), view_labels[k].end());
      seen_by.insert(seen_by.end(), static_cast<std::size_t>(views[k].points.rows()), k);
    }
    merged = to_point_cloud(pts);
    r.registration_seconds = seconds_since(t0);

    // Cloud filters (MLS, stalk removal, downsampling...) on the registered cloud.
    t0 = std::chrono::steady_clock::now();
    const auto count = [&](Part part) {
      return static_cast<double>(std::count(labels.begin(), labels.end(), static_cast<std::uint8_t>(part)));
    };
    const double peduncle_before = count(Part::Peduncle), body_before = static_cast<double>(kept_bunch) - peduncle_before;
    std::vector<std::pair<std::uint8_t, std::size_t>> carried(labels.size());
    for (std::size_t i = 0; i < labels.size(); ++i) carried[i] = {labels[i], seen_by[i]};
    apply_filters(pl.cloud_filters, merged, carried);
    labels.resize(carried.size());
    viewpoints.resize(merged.rows(), 3);
    for (std::size_t i = 0; i < carried.size(); ++i) {
      labels[i] = carried[i].first;
      viewpoints.row(static_cast<Eigen::Index>(i)) = poses[carried[i].second].translation().transpose();
    }
    if (!pl.cloud_filters.empty()) {
      r.peduncle_kept = peduncle_before > 0 ? count(Part::Peduncle) / peduncle_before : 0;
      const double body_after = static_cast<double>(std::count_if(labels.begin(), labels.end(), is_bunch)) - count(Part::Peduncle);
      r.body_kept = body_before > 0 ? body_after / body_before : 0;
    }
    r.filter_seconds = seconds_since(t0);
    r.points = static_cast<std::size_t>(merged.rows());
    if (static_cast<double>(merged.rows()) < pl.min_points) {
      throw InputError("only " + std::to_string(merged.rows()) + " bunch points (pipeline.min_points " +
                       std::to_string(static_cast<long long>(pl.min_points)) + ")");
    }
    r.ok = true;
  } catch (const std::exception& e) {
    r.ok = false;
    r.error = e.what();
  }
  if (scene.pipeline.registration == "single_frame") return r;  // its rows are per frame
  r.rows = run_estimators(scene.estimators, merged, viewpoints, gt, r.ok ? "" : "no cloud: " + r.error);
  if (scene.pipeline.visibility_hull > 0) r.rows.push_back(floor_row);
  return r;
}

}  // namespace grapebench
