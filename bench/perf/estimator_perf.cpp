// Google Benchmark: each estimator on a registered bunch: 12 Kinect v2 turntable
// views (seed 000 protocol) merged with their true poses, bunch points only.
#include "algorithms/volume/alpha_shape_volume.h"
#include "algorithms/volume/convex_hull_volume.h"
#include "algorithms/volume/cylinder_model_volume.h"
#include "algorithms/size/pca_box.h"
#include "algorithms/volume/poisson_volume.h"
#include "algorithms/volume/voxel_volume.h"
#include "sensors/kinect_v2.h"
#include "sensors/scan.h"
#include "synth/generate.h"
#include "synth/ground_truth.h"

#include <benchmark/benchmark.h>

#include <cstdio>

namespace {

using namespace grapebench;

struct Registered {
  PointCloud cloud;
  double true_volume = 0;
};

const Registered& registered() {
  static const Registered r = [] {
    const BunchParams p = preset("table-red");
    const Bunch b = generate_bunch(p, 7);
    const RayScene scene(b);
    const Scan scan = scan_bunch(scene, KinectV2(KinectV2Params{}), *make_turntable(TurntableParams{}), BackgroundSpec{}, 1);
    std::vector<Vec3> pts;
    for (const auto& v : scan.views) {
      for (std::size_t i = 0; i < v.cloud.size(); ++i) {
        if (v.cloud.valid[i] && v.cloud.label[i] != static_cast<std::uint8_t>(Part::Background)) {
          pts.push_back(v.rig.pose * v.cloud.xyz[i].cast<double>());
        }
      }
    }
    Registered out{to_point_cloud(pts), compute_ground_truth(b, p.density).volume.solid};
    std::printf("registered bunch: %zu points, true volume %.1f cm3\n", pts.size(), out.true_volume * 1e6);
    return out;
  }();
  return r;
}

template <class F>
void run(benchmark::State& state, F estimate) {
  const Registered& r = registered();
  double v = 0;
  for (auto _ : state) {
    v = estimate(r.cloud);
    benchmark::DoNotOptimize(&v);  // the address: see frame_perf.cpp (google/benchmark#903)
  }
  state.counters["points"] = static_cast<double>(r.cloud.rows());
  state.counters["volume_cm3"] = v * 1e6;
  state.counters["error_pct"] = 100 * (v / r.true_volume - 1);
}

void BM_PcaBox(benchmark::State& s) { run(s, [](const PointCloud& c) { return pca_box(c).volume(); }); }
void BM_GM(benchmark::State& s) { run(s, [](const PointCloud& c) { return cylinder_model_volume(c).volume; }); }
void BM_CH(benchmark::State& s) { run(s, [](const PointCloud& c) { return convex_hull_volume(c).volume; }); }
void BM_VB_10mm(benchmark::State& s) { run(s, [](const PointCloud& c) { return voxel_volume(c, {0.01, true, 2e8}).volume; }); }
void BM_VB_5mm(benchmark::State& s) { run(s, [](const PointCloud& c) { return voxel_volume(c, {0.005, true, 2e8}).volume; }); }
void BM_AS_25mm(benchmark::State& s) { run(s, [](const PointCloud& c) { return alpha_shape_volume(c, {0.025}).volume; }); }

void BM_PB_depth8(benchmark::State& s) { run(s, [](const PointCloud& c) { return poisson_volume(c).volume; }); }

}  // namespace

BENCHMARK(BM_PB_depth8)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_PcaBox)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_GM)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_CH)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_VB_10mm)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_VB_5mm)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_AS_25mm)->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
