#include "bench/protocols/capture.h"

#include <algorithm>
#include <cmath>

#include "synth/generate.h"
#include "synth/rng.h"
#include "synth/utf8.h"

namespace grapebench {

namespace {

struct CaptureScene {
  Bunch bunch;
  GroundTruth truth;
  RayScene rays;
};

// The bunch from its seed, its truth and the ray scene the rig's views are cast into.
CaptureScene capture_scene(const Scene& scene, const BunchJob& job) {
  if (!scene.sensor || !scene.rig) throw InputError(scene.path + ": a run needs `sensor:` and `rig:` sections");
  Bunch bunch = generate_bunch(job.params, job.seed);
  GroundTruth truth = compute_ground_truth(bunch, job.params.density);
  RayScene rays = scene_rays(scene, bunch, job.seed);
  return {std::move(bunch), std::move(truth), std::move(rays)};
}

// A case that failed: its reason, and one failed row of quantity `case` per estimator
// carrying it, so results.csv and the leaderboard show the failure (issue 38, item 9:
// a crashed or overrunning Blender left the case without a row, the run's tables
// silent about it).
void mark_failed(CaseResult& r, const std::exception& e, const std::vector<EstimatorSpec>& estimators) {
  r.ok = false;
  r.error = escape_invalid_utf8(e.what());
  for (const EstimatorSpec& spec : estimators) {
    EstimateRow row;
    row.estimator = spec.name;
    row.type = spec.type;
    row.quantity = "case";
    row.estimate = NAN;
    row.error = "case failed: " + r.error;
    r.rows.push_back(std::move(row));
  }
}

}  // namespace

std::uint64_t scan_seed(const BunchJob& job) { return derive_seed(job.seed, 0x5ca9); }

CaseCapture capture_case(const Scene& scene, const BunchJob& job) {
  CaptureScene c = capture_scene(scene, job);
  Scan scan = scan_bunch(c.rays, *scene.sensor, *scene.rig, scene.background, scan_seed(job));
  return {std::move(c.bunch), std::move(c.truth), std::move(c.rays), std::move(scan)};
}

EstimatorInput image_input(const ScanView& view) {
  const OrganisedCloud& c = view.cloud;
  if (c.left_image.empty())
    throw InputError("the sensor gives no colour image (use sensor type stereo_rgb)");
  auto pair = std::make_shared<StereoPair>();
  pair->left = {c.width, c.height, c.left_image};
  if (!c.right_image.empty()) pair->right = {c.width, c.height, c.right_image};
  const Intrinsics& k = view.camera.K;
  pair->fx = k.fx, pair->fy = k.fy;
  pair->cx = k.opencv_cx(), pair->cy = k.opencv_cy();
  pair->baseline = c.baseline;
  EstimatorInput in;
  in.stereo = std::move(pair);
  in.frame = InputFrame{-1, "", -1, k.width, k.height, k.fx, k.fy, k.opencv_cx(), k.opencv_cy()};
  return in;
}

CaseResult guarded_case(const Condition& condition, int condition_index, const BunchJob& job,
                        const std::function<void(CaseResult&)>& body) {
  CaseResult r = new_case(condition, condition_index, job);
  try {
    body(r);
    r.ok = true;
  } catch (const std::exception& e) {
    mark_failed(r, e, condition.scene.estimators);
  }
  return r;
}

CaseResult measure_views(const Condition& condition, int condition_index, const BunchJob& job,
                         const ViewMeasure& measure, const std::function<void(CaseResult&)>& finish) {
  // The one-condition case of measure_views_together, then `finish` when every view measured.
  const Condition* const one = &condition;
  CaseResult r = std::move(measure_views_together(std::span<const Condition* const>(&one, 1),
                                                  std::span<const int>(&condition_index, 1), job,
                                                  [&](std::size_t, const Bunch& bunch, const GroundTruth& truth,
                                                      const ScanView& view, std::size_t k, CaseResult& x) {
                                                    measure(bunch, truth, view, k, x);
                                                  })
                               .at(0));
  if (!r.ok || !finish) return r;
  try {
    finish(r);
  } catch (const std::exception& e) {
    mark_failed(r, e, condition.scene.estimators);
  }
  return r;
}

std::vector<CaseResult> measure_views_together(std::span<const Condition* const> conditions,
                                               std::span<const int> condition_indices, const BunchJob& job,
                                               const ViewsMeasure& measure) {
  const std::size_t n = conditions.size();
  std::vector<CaseResult> r;
  for (std::size_t c = 0; c < n; ++c) r.push_back(new_case(*conditions[c], condition_indices[c], job));
  std::vector<char> failed(n, 0);
  const auto fail = [&](std::size_t c, const std::exception& e) {
    failed[c] = 1;
    mark_failed(r[c], e, conditions[c]->scene.estimators);
  };
  try {
    const Scene& scene = conditions.front()->scene;
    std::vector<const Sensor*> sensors;
    for (const Condition* c : conditions) {
      if (!c->scene.sensor || !c->scene.rig) throw InputError(c->scene.path + ": a run needs `sensor:` and `rig:` sections");
      sensors.push_back(c->scene.sensor.get());
    }
    const auto t0 = std::chrono::steady_clock::now();
    const CaptureScene cs = capture_scene(scene, job);
    const double build = seconds_since(t0) / static_cast<double>(n);
    for (CaseResult& x : r) x.scan_seconds = build, x.views = 0;
    scan_views_together(cs.rays, sensors, *scene.rig, scene.background, scan_seed(job),
                        [&](std::vector<ScanView>&& views, std::size_t k) {
                          for (std::size_t c = 0; c < n; ++c) {
                            if (failed[c]) continue;  // no view of a case after the one that failed it
                            r[c].scan_seconds += views[c].seconds;
                            ++r[c].views;
                            try {
                              measure(c, cs.bunch, cs.truth, views[c], k, r[c]);
                            } catch (const std::exception& e) {
                              fail(c, e);
                            }
                          }
                          // Go on while a case is live: once every case failed, no further capture.
                          return std::find(failed.begin(), failed.end(), 0) != failed.end();
                        });
    for (std::size_t c = 0; c < n; ++c) r[c].ok = !failed[c];
  } catch (const std::exception& e) {
    for (std::size_t c = 0; c < n; ++c) {
      if (!failed[c]) fail(c, e);
    }
  }
  return r;
}

}  // namespace grapebench
