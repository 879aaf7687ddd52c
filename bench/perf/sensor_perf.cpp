// Google Benchmark: rays per second of each sensor on each rig, against the raw
// Embree cast loop (16-ray packets, no model) on the same rays in the same run.
#include "sensors/d435.h"
#include "sensors/ideal.h"
#include "sensors/kinect_v2.h"
#include "sensors/rig.h"
#include "sensors/scan.h"
#include "synth/generate.h"

#include <benchmark/benchmark.h>
#include <tbb/global_control.h>

#include <memory>

namespace {

using namespace grapebench;

const Bunch& bunch() {
  static const Bunch b = generate_bunch(preset("table-red"), 7);
  return b;
}
const RayScene& scene() {
  static const RayScene s(bunch());
  return s;
}

std::unique_ptr<Sensor> sensor(const std::string& type) {
  if (type == "kinect_v2") return std::make_unique<KinectV2>(KinectV2Params{});
  if (type == "d435") return std::make_unique<D435>(D435Params{});
  return std::make_unique<IdealSensor>(IdealParams{});
}

std::unique_ptr<Rig> rig(const std::string& type) {
  if (type == "turntable12") return make_turntable(TurntableParams{});
  if (type == "turntable8_bottom") {
    TurntableParams p;
    p.views = 8;
    p.step_deg = 45;
    p.bottom_view = true;
    return make_turntable(p);
  }
  if (type == "robot_pass") return make_robot_pass(RobotPassParams{});
  return make_stereo_stations(StereoStationsParams{});
}

// The rays an ideal or D435 model traces through Embree for one view: its pixel
// centres inside the bunch's image bounds, n x n per pixel.
std::vector<Ray> traced_rays(const Sensor& s, const Eigen::Isometry3d& pose, int n) {
  const Camera cam{s.intrinsics(), pose};
  int u0, v0, u1, v1;
  std::vector<Ray> rays;
  if (!cam.ball_pixels(scene().bounds_centre(), scene().bounds_radius(), u0, v0, u1, v1)) return rays;
  for (int v = v0; v < v1; ++v)
    for (int u = u0; u < u1; ++u)
      for (int a = 0; a < n; ++a)
        for (int b = 0; b < n; ++b) rays.push_back(cam.ray(u + (b + 0.5) / n, v + (a + 0.5) / n));
  return rays;
}

void BM_Sensor(benchmark::State& state, std::string sensor_type, std::string rig_type) {
  // One thread, like the raw loop it is compared with.
  tbb::global_control one_thread(tbb::global_control::max_allowed_parallelism, 1);
  const auto s = sensor(sensor_type);
  const auto r = rig(rig_type);
  (void)scene();  // built before the timing, whichever benchmark interleaving runs first
  std::uint64_t rays = 0;
  for (auto _ : state) {
    const Scan scan = scan_bunch(scene(), *s, *r, BackgroundSpec{}, 5);
    for (const auto& v : scan.views) rays += v.cloud.rays_cast;
  }
  state.counters["rays_per_s"] = benchmark::Counter(static_cast<double>(rays), benchmark::Counter::kIsRate);
  state.counters["views"] = static_cast<double>(r->views(scene().bounds_centre(), scene().bounds_radius(), {}).size());
}

void BM_RawEmbree(benchmark::State& state, std::string sensor_type, std::string rig_type) {
  const auto s = sensor(sensor_type);
  const auto r = rig(rig_type);
  std::vector<std::vector<Ray>> views;
  // The D435 also traces, for each hit, the segments to its right imager and projector
  // that can cross the bunch (the others cannot be blocked and are not traced).
  std::vector<std::vector<Vec3>> from, to;
  const auto poses = r->views(scene().bounds_centre(), scene().bounds_radius(), {});
  for (std::size_t k = 0; k < poses.size(); ++k) {
    const auto& v = poses[k];
    // The Kinect's rays, jitter and margin included, exactly as its capture traces
    // them (the seed view_seed gives scan_bunch's view k).
    if (sensor_type == "kinect_v2") {
      views.push_back(static_cast<const KinectV2&>(*s).traced_rays(scene(), v.pose, view_seed(5, k)));
    } else {
      views.push_back(traced_rays(*s, v.pose, 1));
    }
    from.emplace_back();
    to.emplace_back();
    if (sensor_type != "d435") continue;
    std::vector<Hit> hits;
    scene().intersect(views.back(), hits);
    const D435Params dp;
    const double br2 = scene().bounds_radius() * scene().bounds_radius();
    for (const auto& h : hits) {
      if (!h.valid()) continue;
      for (const Vec3& o : {Vec3(v.pose * Vec3(dp.baseline, 0, 0)), Vec3(v.pose * Vec3(dp.projector_x, dp.projector_y, 0))}) {
        if (point_segment_distance_sq(scene().bounds_centre(), o, h.point) > br2) continue;
        from.back().push_back(o);
        to.back().push_back(h.point);
      }
    }
  }
  std::uint64_t rays = 0, hits = 0;
  std::vector<char> blocked;
  for (auto _ : state) {
    for (std::size_t k = 0; k < views.size(); ++k) {
      hits += scene().raw_intersect_count(views[k]);
      rays += views[k].size();
      if (!from[k].empty()) {
        scene().occluded(from[k], to[k], blocked);
        rays += from[k].size();
      }
    }
  }
  benchmark::DoNotOptimize(hits);
  state.counters["rays_per_s"] = benchmark::Counter(static_cast<double>(rays), benchmark::Counter::kIsRate);
}

#define SENSOR_RIG(s, r)                                                                              \
  BENCHMARK_CAPTURE(BM_RawEmbree, s##_##r, std::string(#s), std::string(#r))->Unit(benchmark::kMillisecond); \
  BENCHMARK_CAPTURE(BM_Sensor, s##_##r, std::string(#s), std::string(#r))->Unit(benchmark::kMillisecond)

SENSOR_RIG(kinect_v2, turntable12);
SENSOR_RIG(kinect_v2, turntable8_bottom);
SENSOR_RIG(d435, robot_pass);
SENSOR_RIG(d435, turntable12);
SENSOR_RIG(ideal, stereo_stations);
SENSOR_RIG(ideal, turntable12);

}  // namespace

BENCHMARK_MAIN();
