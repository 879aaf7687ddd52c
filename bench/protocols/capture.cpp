#include "bench/protocols/capture.h"

#include "synth/generate.h"
#include "synth/rng.h"

namespace grapebench {

CaseCapture capture_case(const Scene& scene, const BunchJob& job) {
  if (!scene.sensor || !scene.rig) throw InputError(scene.path + ": a run needs `sensor:` and `rig:` sections");
  Bunch bunch = generate_bunch(job.params, job.seed);
  GroundTruth truth = compute_ground_truth(bunch, job.params.density);
  RayScene rays = scene_rays(scene, bunch, job.seed);
  Scan scan = scan_bunch(rays, *scene.sensor, *scene.rig, scene.background, derive_seed(job.seed, 0x5ca9));
  return {std::move(bunch), std::move(truth), std::move(rays), std::move(scan)};
}

CaseResult measure_views(const Condition& condition, int condition_index, const BunchJob& job,
                         const ViewMeasure& measure, const std::function<void(CaseResult&)>& finish) {
  CaseResult r = new_case(condition, condition_index, job);
  try {
    const Scene& scene = condition.scene;
    if (!scene.sensor || !scene.rig) throw InputError(scene.path + ": a run needs `sensor:` and `rig:` sections");
    const auto t0 = std::chrono::steady_clock::now();
    const Bunch bunch = generate_bunch(job.params, job.seed);
    const GroundTruth truth = compute_ground_truth(bunch, job.params.density);
    const RayScene rays = scene_rays(scene, bunch, job.seed);
    r.scan_seconds = seconds_since(t0);
    r.views = 0;
    scan_views(rays, *scene.sensor, *scene.rig, scene.background, derive_seed(job.seed, 0x5ca9),
               [&](ScanView&& view, std::size_t k) {
                 r.scan_seconds += view.seconds;
                 ++r.views;
                 measure(bunch, truth, view, k, r);
               });
    if (finish) finish(r);
    r.ok = true;
  } catch (const std::exception& e) {
    r.ok = false;
    r.error = e.what();
  }
  return r;
}

}  // namespace grapebench
