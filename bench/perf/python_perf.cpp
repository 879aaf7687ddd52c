// Google Benchmark (issue 41, item 6): what one call of a Python estimator costs in
// the harness, in-process (`type: python`) against the same function as a persistent
// external program (`type: external, version: 2, persistent: true`), on the input a
// multi_view case hands over (cloud, normals, viewpoints; N points on a 5 cm sphere).
//   constant: a function that does no work (bench/perf/python/overhead_estimator.py),
//             so the time is the hand-over alone: the per-call overhead;
//   hull:     Open3D's convex hull (scripts/external/open3d_estimator.py), a real
//             estimator: overhead plus the same work.
// The external side runs the function through scripts/external/serve_python.py (PLY
// files in, a JSON line out), without the sandbox, which costs nothing per call once
// started. Estimators are created outside the timing: the import, or the process
// start, is paid once per run.
// Ratios: run with --benchmark_repetitions=5 --benchmark_enable_random_interleaving=true
// and divide external by in-process per argument; quote the worst.
#include "algorithms/registry.h"
#include "synth/config.h"

#include <benchmark/benchmark.h>

#include <cmath>
#include <map>
#include <memory>
#include <string>

namespace {

using namespace grapebench;

const std::string kSource = GRAPEBENCH_SOURCE_DIR;

// Fibonacci points on a 5 cm sphere with their normals, seen from 0.5 m along them.
EstimatorInput sphere_input(long n) {
  EstimatorInput in;
  in.points.resize(n, 3);
  in.normals.resize(n, 3);
  in.viewpoints.resize(n, 3);
  for (long i = 0; i < n; ++i) {
    const double z = 1 - 2 * (static_cast<double>(i) + 0.5) / static_cast<double>(n);
    const double phi = M_PI * (3 - std::sqrt(5.0)) * static_cast<double>(i), s = std::sqrt(1 - z * z);
    const Vec3 u(s * std::cos(phi), s * std::sin(phi), z);
    in.points.row(i) = 0.05 * u;
    in.normals.row(i) = u;
    in.viewpoints.row(i) = 0.55 * u;
  }
  return in;
}

const EstimatorBinding& bound(const std::string& yaml) {
  static std::map<std::string, std::unique_ptr<EstimatorBinding>> made;
  auto& b = made[yaml];
  if (!b) {
    nlohmann::ordered_json params;
    b = std::make_unique<EstimatorBinding>(estimator_registry().create(ConfigNode::load_string(yaml, "perf"), params));
  }
  return *b;
}

std::string in_process(const std::string& folder, const std::string& module, const std::string& function) {
  return "{type: python, module: " + module + ", function: " + function + ", path: [\"" + kSource + "/" + folder +
         "\"]}";
}

std::string external(const std::string& folder, const std::string& module, const std::string& function) {
  return "{type: external, version: 2, persistent: true, sandbox: none, command: [/usr/bin/python3, \"" + kSource +
         "/scripts/external/serve_python.py\", --path, \"" + kSource + "/" + folder + "\", " + module + ", " +
         function + "]}";
}

void call(benchmark::State& state, const std::string& yaml) {
  const EstimatorInput in = sphere_input(state.range(0));
  const EstimatorBinding& b = bound(yaml);
  double v = b.run(in).values.at(0).second;  // warm: the first call of a persistent program starts it
  for (auto _ : state) {
    v = b.run(in).values.at(0).second;
    benchmark::DoNotOptimize(&v);  // the address: see frame_perf.cpp (google/benchmark#903)
  }
  state.counters["points"] = static_cast<double>(state.range(0));
  state.counters["volume_cm3"] = v * 1e6;
}

const std::string kOverhead = "bench/perf/python", kOpen3d = "scripts/external";

}  // namespace

BENCHMARK_CAPTURE(call, constant_in_process, in_process(kOverhead, "overhead_estimator", "constant"))
    ->Arg(3000)->Arg(30000)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(call, constant_external_persistent, external(kOverhead, "overhead_estimator", "constant"))
    ->Arg(3000)->Arg(30000)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(call, hull_in_process, in_process(kOpen3d, "open3d_estimator", "estimate"))
    ->Arg(3000)->Arg(30000)->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(call, hull_external_persistent, external(kOpen3d, "open3d_estimator", "estimate"))
    ->Arg(3000)->Arg(30000)->Unit(benchmark::kMicrosecond);

BENCHMARK_MAIN();
