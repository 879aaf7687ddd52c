#include "bench/scan_run.h"

#include "bench/protocols/capture.h"
#include "sensors/render/cycles_render.h"
#include "synth/generate.h"
#include "synth/ground_truth.h"
#include "synth/io.h"
#include "synth/mesh.h"

#include <tbb/global_control.h>
#include <tbb/info.h>

#include <cstdio>
#include <sstream>

namespace grapebench {

std::vector<ScanSummary> run_scans(const Scene& scene, const ScanRunOptions& o) {
  if (!scene.sensor || !scene.rig) {
    throw InputError(scene.path + ": scanning needs `sensor:` and `rig:` sections");
  }
  const int threads = o.threads > 0 ? o.threads : static_cast<int>(tbb::info::default_concurrency());
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
  const CyclesCacheScope cache(o.cycles_cache);
  std::vector<ScanSummary> rows;
  std::vector<BunchJob> jobs;
  for (const auto& job : bunch_jobs(scene)) {
    if (o.only_bunch < 0 || job.index == o.only_bunch) jobs.push_back(job);
  }
  if (jobs.empty()) {
    throw InputError(scene.path + ": --bunch " + std::to_string(o.only_bunch) + " is not in the scene (bunches 0.." +
                     std::to_string(bunch_jobs(scene).size() - 1) + ")");
  }
  Progress progress("bunch", static_cast<int>(jobs.size()), o.verbosity);
  for (const auto& job : jobs) {
    GenerationReport report;
    const Bunch bunch = generate_bunch(job.params, job.seed, &report);
    char stem[32];
    std::snprintf(stem, sizeof stem, "bunch_%04d", job.index);
    const auto dir = o.out / stem;
    std::filesystem::create_directories(dir);
    const GroundTruth truth = compute_ground_truth(bunch, job.params.density);
    const BunchRecord rec{job.preset, job.seed, job.index, job.params, report};
    write_file_atomic(dir / "ground_truth.json", ground_truth_json(bunch, truth, rec).dump(1) + "\n");
    const RayScene rays = scene_rays(scene, bunch, job.seed);
    // Each view is written as it is captured: a pass of a thousand frames holds one.
    const std::uint64_t seed = scan_seed(job);  // its own stream, independent of the generator's
    ScanWriter writer(scan_description(*scene.sensor, *scene.rig, scene.background, seed), dir, stem, o.merged);
    ScanSummary s;
    s.bunch = job.index;
    scan_views(rays, *scene.sensor, *scene.rig, scene.background, seed, [&](ScanView&& v, std::size_t) {
      writer.add(v);
      ++s.views;
      s.valid_points += v.cloud.valid_count();
      s.rays += v.cloud.rays_cast;
      s.seconds += v.seconds;
    });
    writer.finish();
    rows.push_back(s);
    progress.done("bunch " + std::to_string(job.index) + ", " + std::to_string(s.views) + " views");
  }
  return rows;
}

std::string scan_summary_table(const std::vector<ScanSummary>& rows) {
  std::ostringstream s;
  char line[160];
  std::snprintf(line, sizeof line, "%5s %6s %12s %12s %10s %10s\n", "bunch", "views", "points", "rays", "seconds",
                "Mrays/s");
  s << line;
  for (const auto& r : rows) {
    std::snprintf(line, sizeof line, "%5d %6d %12zu %12llu %10.3f %10.1f\n", r.bunch, r.views, r.valid_points,
                  static_cast<unsigned long long>(r.rays), r.seconds, r.rays / std::max(r.seconds, 1e-9) / 1e6);
    s << line;
  }
  return s.str();
}

}  // namespace grapebench
