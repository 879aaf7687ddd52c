// Occlusion, mixed pixels, exactness and determinism of the sensor models on bunches.
#include "sensors/d435.h"
#include "sensors/ideal.h"
#include "sensors/kinect_v2.h"
#include "sensors/rig.h"
#include "sensors/scan.h"
#include "synth/generate.h"
#include "synth/stem_geometry.h"

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <cstdio>

namespace grapebench {
namespace {

Bunch test_bunch() { return generate_bunch(preset("table-red"), 21); }

Eigen::Isometry3d front_pose(const RayScene& s, double distance) {
  const Vec3 c = s.bounds_centre();
  return look_at(c - Vec3(0, distance, 0.05), c);
}

// Unsigned distance from x to the surface of the nearest primitive of the bunch.
double distance_to_surface(const Bunch& b, const Vec3& x) {
  double best = 1e30;
  for (const auto& be : b.berries) best = std::min(best, std::abs((x - be.centre).norm() - be.radius));
  for (const auto& s : b.stems) {
    const Vec3 w = (s.end - s.start).normalized();
    const double len = (s.end - s.start).norm(), a = (x - s.start).dot(w);
    const double r = ((x - s.start) - a * w).norm();
    double d;
    if (a >= 0 && a <= len) d = std::min(std::abs(r - s.radius), r <= s.radius ? std::min(a, len - a) : 1e30);
    else d = std::hypot(std::max(0.0, r - s.radius), a < 0 ? -a : a - len);
    best = std::min(best, d);
  }
  return best;
}

// Independent visibility: does the open segment from `eye` to `p` cross any berry or
// stem? Brute force in double, no Embree.
bool hidden(const Bunch& b, const Vec3& eye, const Vec3& p) {
  const Vec3 d = (p - eye).normalized();
  const double len = (p - eye).norm() - 1e-6;
  for (const auto& be : b.berries) {
    const Vec3 oc = eye - be.centre;
    const double bq = oc.dot(d), c = oc.squaredNorm() - be.radius * be.radius, disc = bq * bq - c;
    if (disc <= 0) continue;
    const double t0 = -bq - std::sqrt(disc), t1 = -bq + std::sqrt(disc);
    if (t1 > 1e-6 && t0 < len - 1e-6 && std::max(t0, 0.0) < len - 1e-6 && (t1 - std::max(t0, 0.0)) > 2e-6) return true;
  }
  for (const auto& s : b.stems) {
    if (segment_segment_distance(eye, p, s.start, s.end) > s.radius) continue;
    // Sample the segment densely against the exact cylinder (the stems are thin).
    const int n = 4000;
    for (int k = 1; k < n; ++k) {
      const Vec3 x = eye + (len * k / n) * d;
      if ((x - p).norm() > 1e-5 && inside_stem(s, x) && distance_to_surface(b, x) > 2e-6) return true;
    }
  }
  return false;
}

TEST(Sensors, IdealPointsLieOnTheTrueSurface) {
  const Bunch b = test_bunch();
  const RayScene scene(b);
  const auto pose = front_pose(scene, 0.6);
  const OrganisedCloud c = IdealSensor(IdealParams{}).capture(scene, pose, 0);
  double worst = 0;
  std::size_t n = 0;
  for (std::size_t i = 0; i < c.size(); ++i) {
    if (!c.valid[i]) continue;
    worst = std::max(worst, distance_to_surface(b, pose * c.xyz[i].cast<double>()));
    ++n;
  }
  std::printf("[ideal] %zu points, farthest from the true surface %.2e m\n", n, worst);
  EXPECT_GT(n, 5000u);
  EXPECT_LT(worst, 1e-5);
}

TEST(Sensors, SkippingPixelsThatCannotSeeTheBunchChangesNothing) {
  const Bunch b = test_bunch();
  const RayScene scene(b);
  const auto pose = front_pose(scene, 0.8);
  const IdealSensor ideal(IdealParams{});
  const OrganisedCloud c = ideal.capture(scene, pose, 0);
  const Camera cam{ideal.intrinsics(), pose};
  std::vector<Ray> rays;
  for (int v = 0; v < cam.K.height; ++v)
    for (int u = 0; u < cam.K.width; ++u) rays.push_back(cam.ray(u + 0.5, v + 0.5));
  std::vector<Hit> hits;
  scene.intersect(rays, hits);
  for (std::size_t i = 0; i < rays.size(); ++i) ASSERT_EQ(hits[i].valid(), c.valid[i] == 1) << "pixel " << i;
  EXPECT_LT(c.rays_cast, rays.size() / 4);  // most of the frame was never traced
}

// Frames without a background declare the rows their valid and label maps can change
// in, and recycled frames are refilled only there: a sensor writing outside them, or
// a stale recycled map, would show here (the frame pool is active in Release builds).
TEST(Sensors, FramesChangeTheirMapsOnlyInTheDeclaredRowsAndRecycleClean) {
  const Bunch b = test_bunch();
  const RayScene scene(b);
  const Vec3 c = scene.bounds_centre();
  const auto high = look_at(c - Vec3(0, 0.6, 0.25), c - Vec3(0, 0, 0.2));  // bunch low in the frame
  const auto low = look_at(c - Vec3(0, 1.2, -0.2), c + Vec3(0, 0, 0.25));  // bunch high in the frame
  const KinectV2 kinect(KinectV2Params{});
  const D435 d435(D435Params{});
  const IdealSensor ideal(IdealParams{});
  for (const Sensor* s : std::initializer_list<const Sensor*>{&kinect, &d435, &ideal}) {
    SCOPED_TRACE(s->type());
    const std::string first = pcd_bytes(s->capture(scene, high, 4));
    { const OrganisedCloud other = s->capture(scene, low, 5); }  // its maps go back to the pool
    const OrganisedCloud again = s->capture(scene, high, 4);
    EXPECT_EQ(first, pcd_bytes(again));
    const ByteMap& label = again.label;
    ASSERT_LT(label.writes_begin(), label.writes_end());
    ASSERT_LT(label.writes_end() - label.writes_begin(), again.size() / 2);  // the bunch's rows only
    for (std::size_t i = 0; i < again.size(); ++i) {
      if (i >= label.writes_begin() && i < label.writes_end()) continue;
      ASSERT_EQ(label[i], static_cast<std::uint8_t>(Part::None)) << "pixel " << i;
      ASSERT_EQ(again.valid[i], 0) << "pixel " << i;
    }
  }
}

TEST(Sensors, NoReturnIsAHiddenSurfacePoint) {
  const Bunch b = test_bunch();
  const RayScene scene(b);
  const auto pose = front_pose(scene, 0.5);
  D435Params dp;
  dp.noise_scale = 0;
  dp.width = 424;
  dp.height = 240;
  const D435 d435(dp);
  const OrganisedCloud c = d435.capture(scene, pose, 0);
  const Camera cam{d435.intrinsics(), pose};
  const Vec3 right = pose * Vec3(dp.baseline, 0, 0), projector = pose * Vec3(dp.projector_x, 0, 0);
  std::size_t checked = 0, shadowed = 0;
  for (int v = 0; v < cam.K.height; ++v) {
    for (int u = 0; u < cam.K.width; ++u) {
      const std::size_t i = static_cast<std::size_t>(v) * cam.K.width + u;
      if (c.truth(i) <= 0) continue;
      const Ray r = cam.ray(u + 0.5, v + 0.5);
      const Vec3 dir_cam = pose.linear().transpose() * r.direction;
      const Vec3 p = r.origin + (c.true_depth[i] / dir_cam.z()) * r.direction;
      const bool seen_left = !hidden(b, cam.centre(), p);
      const bool seen_right = !hidden(b, right, p), lit = !hidden(b, projector, p);
      if (c.valid[i]) {
        ASSERT_TRUE(seen_left && seen_right && lit) << "pixel " << u << "," << v;
        ++checked;
      } else if (seen_left && (!seen_right || !lit)) {
        ++shadowed;
      }
    }
  }
  std::printf("[occlusion] %zu returns checked visible from both imagers and the projector; %zu shadowed\n",
              checked, shadowed);
  EXPECT_GT(checked, 2000u);
  EXPECT_GT(shadowed, 40u);  // the D435's occlusion shadows exist
}

TEST(Sensors, FlyingPixelsOnlyAtDepthDiscontinuitiesAndGoneWithEdgeFilter) {
  const Bunch b = test_bunch();
  BackgroundPlane plate{-Vec3::UnitY(), 0, {0.4f, 0.4f, 0.4f}, 0.5};
  plate.offset = plate.normal.dot(Vec3(0, 0.25, 0));
  const RayScene scene(b, plate);
  const auto pose = front_pose(scene, 0.7);
  KinectV2Params p;
  p.noise_scale = 0;
  p.edge_filter = false;
  auto count = [&](const KinectV2Params& params, std::size_t* at_edges) {
    const OrganisedCloud c = KinectV2(params).capture(scene, pose, 0);
    std::size_t flying = 0, edges = 0;
    for (int v = 1; v + 1 < c.height; ++v) {
      for (int u = 1; u + 1 < c.width; ++u) {
        const std::size_t i = static_cast<std::size_t>(v) * c.width + u;
        // Flying: in mid-air, farther than the filter's tolerance from every true
        // surface depth in the 3 x 3 neighbourhood (a blend across a smaller step is
        // ordinary surface blur, which no neighbour-difference filter can tell apart).
        if (!c.valid[i]) continue;
        const double tol = std::max(params.edge_abs, params.edge_rel * c.truth(i));
        bool on_surface = false;
        for (int dv = -1; dv <= 1; ++dv)
          for (int du = -1; du <= 1; ++du) {
            const float t = c.truth((v + dv) * c.width + u + du);
            on_surface = on_surface || (t > 0 && std::abs(c.xyz[i].z() - t) < tol);
          }
        if (on_surface) continue;
        ++flying;
        float lo = 1e9f, hi = -1e9f;
        for (int dv = -1; dv <= 1; ++dv)
          for (int du = -1; du <= 1; ++du) {
            const float t = c.truth((v + dv) * c.width + u + du);
            lo = std::min(lo, t > 0 ? t : 1e9f);
            hi = std::max(hi, t > 0 ? t : 1e9f);
          }
        edges += hi - lo > tol;  // a depth step in the neighbourhood
      }
    }
    if (at_edges) *at_edges = edges;
    return flying;
  };
  std::size_t at_edges = 0;
  const std::size_t flying = count(p, &at_edges);
  std::printf("[flying] without edge filter: %zu mixed pixels, %zu at a depth discontinuity\n", flying, at_edges);
  EXPECT_GT(flying, 20u);
  EXPECT_EQ(flying, at_edges);
  p.edge_filter = true;
  EXPECT_EQ(count(p, nullptr), 0u);
}

TEST(Sensors, SameSeedSameBytesAtOneOrTwoThreads) {
  const Bunch b = test_bunch();
  const RayScene scene(b);
  TurntableParams tp;
  tp.views = 2;
  const auto rig = make_turntable(tp);
  BackgroundSpec bg;
  bg.type = BackgroundType::Plate;
  auto bytes = [&](int threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    std::string out;
    for (const Sensor* s : std::initializer_list<const Sensor*>{new KinectV2(KinectV2Params{}), new D435(D435Params{})}) {
      const Scan scan = scan_bunch(scene, *s, *rig, bg, 99);
      for (const auto& v : scan.views) out += pcd_bytes(v.cloud) + depth_png_bytes(v.cloud);
      delete s;
    }
    return out;
  };
  const std::string one = bytes(1);
  EXPECT_EQ(one, bytes(2));
  EXPECT_GT(one.size(), 1000000u);
}

TEST(Rigs, TurntableAndBottomViewPoses) {
  TurntableParams tp;
  tp.views = 8;
  tp.step_deg = 45;
  tp.bottom_view = true;
  const Vec3 centre(0, 0, -0.1);
  const auto views = make_turntable(tp)->views(centre, 0.12, BackgroundSpec{});
  ASSERT_EQ(views.size(), 9u);
  for (int k = 0; k < 8; ++k) {
    const Vec3 eye = views[k].pose.translation();
    EXPECT_NEAR(std::hypot(eye.x(), eye.y()), tp.distance, 1e-12);
    EXPECT_NEAR(eye.z(), tp.camera_height - tp.bunch_top_height, 1e-12);
    EXPECT_NEAR((views[k].pose.linear().col(2) - (centre - eye).normalized()).norm(), 0, 1e-12);
    EXPECT_DOUBLE_EQ(views[k].turntable_angle_deg, 45.0 * k);
  }
  EXPECT_NEAR(views[8].pose.linear().col(2).z(), 1.0, 1e-12);  // looking up
  EXPECT_LT(views[8].pose.translation().z(), centre.z());
}

}  // namespace
}  // namespace grapebench
