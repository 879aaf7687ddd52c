#include "bench/synth_run.h"

#include "synth/alpha_wrap_envelope.h"
#include "synth/io.h"
#include "synth/union_mesh.h"

#include <tbb/global_control.h>
#include <tbb/parallel_for.h>

#include <chrono>
#include <cstdio>
#include <sstream>

namespace grapebench {

std::vector<SynthResult> run_synth(const std::vector<BunchJob>& jobs, const SynthOptions& o) {
  if (!o.out.empty()) std::filesystem::create_directories(o.out);
  const int threads = o.threads > 0 ? o.threads : static_cast<int>(tbb::info::default_concurrency());
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));
  std::vector<SynthResult> results(jobs.size());
  std::vector<std::string> errors(jobs.size());
  Progress progress("bunch", static_cast<int>(jobs.size()), o.verbosity);
  tbb::parallel_for(std::size_t{0}, jobs.size(), [&](std::size_t i) {
    try {
      const auto t0 = std::chrono::steady_clock::now();
      SynthResult& r = results[i];
      r.job = jobs[i];
      const Bunch bunch = generate_bunch(jobs[i].params, jobs[i].seed, &r.report);
      r.truth = compute_ground_truth(bunch, jobs[i].params.density);
      if (o.alpha_wrap > 0) {
        // Offset alpha / 100: a lone berry's wrap within 1.7 % of its ball, against 5.7 % at
        // CGAL's default alpha / 30 (tests/synth/alpha_wrap_envelope_test.cpp).
        r.truth.alpha_wrap_volume = alpha_wrap_envelope(bunch, o.alpha_wrap, o.alpha_wrap / 100).volume;
        r.truth.alpha_wrap_alpha = o.alpha_wrap;
      }
      r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      if (o.out.empty()) {
        progress.done("bunch " + std::to_string(jobs[i].index));
        return;
      }
      char stem[32];
      std::snprintf(stem, sizeof stem, "bunch_%04d", jobs[i].index);
      const BunchRecord rec{jobs[i].preset, jobs[i].seed, jobs[i].index, jobs[i].params, r.report};
      write_file_atomic(o.out / (std::string(stem) + ".json"),
                        ground_truth_json(bunch, r.truth, rec).dump(1) + "\n");
      if (o.write_mesh) {
        const TriMesh mesh = bunch_surface(bunch, o.mesh);
        write_file_atomic(o.out / (std::string(stem) + ".ply"), ply_bytes(mesh));
        write_file_atomic(o.out / (std::string(stem) + ".obj"), obj_text(mesh, "parts.mtl"));
      }
      progress.done("bunch " + std::to_string(jobs[i].index));
    } catch (const std::exception& e) {
      errors[i] = "bunch " + std::to_string(jobs[i].index) + " (" + jobs[i].preset + ", seed " +
                  std::to_string(jobs[i].seed) + "): " + e.what();
    }
  });
  for (const auto& e : errors) {
    if (!e.empty()) throw InputError(e);
  }
  if (!o.out.empty() && o.write_mesh) write_file_atomic(o.out / "parts.mtl", obj_material_library());
  if (!o.out.empty()) write_file_atomic(o.out / "summary.csv", synth_summary_csv(results));
  return results;
}

std::string synth_summary_csv(const std::vector<SynthResult>& results) {
  std::ostringstream s;
  s.precision(10);
  s << "index,preset,seed,berries,solid_volume_cm3,mass_g,envelope_volume_cm3,compactness,"
       "pca_height_m,pca_length_m,pca_width_m,hanging_height_m,max_diameter_m,"
       "cutting_point_x_m,cutting_point_y_m,cutting_point_z_m,contact_pairs,berries_in_contact,"
       "contact_depth_mean,contact_depth_max,berries_removed_by_packing,horizontal_extent_ratio,"
       "wing_berry_share,alpha_wrap_volume_cm3\n";
  for (const auto& r : results) {
    const auto& g = r.truth;
    s << r.job.index << "," << r.job.preset << "," << r.job.seed << "," << g.berry_count << ","
      << g.volume.solid * 1e6 << "," << g.mass << "," << g.envelope_volume * 1e6 << "," << g.compactness
      << "," << g.pca_extent[0] << "," << g.pca_extent[1] << "," << g.pca_extent[2] << "," << g.height
      << "," << g.max_diameter << "," << g.cutting_point.x() << "," << g.cutting_point.y() << ","
      << g.cutting_point.z() << "," << g.contact_pairs << "," << g.berries_in_contact << ","
      << g.contact_depth_mean << "," << g.contact_depth_max << "," << r.report.berries_removed << ","
      << g.horizontal_extent_ratio << "," << g.wing_berry_share << ",";
    if (g.alpha_wrap_alpha > 0) s << g.alpha_wrap_volume * 1e6;
    s << "\n";
  }
  return s.str();
}

std::string synth_summary_table(const std::vector<SynthResult>& results) {
  std::ostringstream s;
  char line[256];
  std::snprintf(line, sizeof line, "%5s  %-12s %7s %10s %8s %9s %7s %18s %8s %8s\n", "bunch", "preset",
                "berries", "volume", "mass", "envelope", "compact", "PCA H x L x W", "hang H", "max D");
  s << line;
  std::snprintf(line, sizeof line, "%5s  %-12s %7s %10s %8s %9s %7s %18s %8s %8s\n", "", "", "", "cm3",
                "g", "cm3", "", "mm", "mm", "mm");
  s << line;
  for (const auto& r : results) {
    const auto& g = r.truth;
    std::snprintf(line, sizeof line, "%5d  %-12s %7d %10.1f %8.1f %9.1f %7.3f %6.0f x%4.0f x%4.0f %8.0f %8.0f\n",
                  r.job.index, r.job.preset.c_str(), g.berry_count, g.volume.solid * 1e6, g.mass,
                  g.envelope_volume * 1e6, g.compactness, g.pca_extent[0] * 1e3, g.pca_extent[1] * 1e3,
                  g.pca_extent[2] * 1e3, g.height * 1e3, g.max_diameter * 1e3);
    s << line;
  }
  return s.str();
}

}  // namespace grapebench
