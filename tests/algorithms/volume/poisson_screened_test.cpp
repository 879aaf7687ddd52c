// The screened Poisson solver, the grid contouring and the closed-mesh test on
// shapes with known answers.
#include "algorithms/volume/grid_contour.h"
#include "algorithms/volume/poisson_screened.h"
#include "algorithms/volume/poisson_volume.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>

namespace grapebench {
namespace {

// Points, outward normals and equal areas on the union of balls (centre, radius):
// Fibonacci points on each sphere, keeping those outside the other balls.
struct Oriented {
  PointCloud points, normals;
  std::vector<double> areas;
};

Oriented balls(const std::vector<std::pair<Vec3, double>>& b, int per_ball) {
  std::vector<Vec3> p, n;
  std::vector<double> a;
  const double g = M_PI * (3 - std::sqrt(5.0));
  for (std::size_t k = 0; k < b.size(); ++k) {
    const auto& [c, r] = b[k];
    for (int i = 0; i < per_ball; ++i) {
      const double z = 1 - (2.0 * i + 1) / per_ball, s = std::sqrt(1 - z * z);
      const Vec3 u(s * std::cos(g * i), s * std::sin(g * i), z);
      const Vec3 x = c + r * u;
      bool covered = false;
      for (std::size_t j = 0; j < b.size(); ++j) covered |= j != k && (x - b[j].first).norm() < b[j].second;
      if (covered) continue;
      p.push_back(x);
      n.push_back(u);
      a.push_back(4 * M_PI * r * r / per_ball);
    }
  }
  return {to_point_cloud(p), to_point_cloud(n), a};
}

double volume_of(const ScreenedPoissonMesh& m) { return std::abs(mesh_signed_volume(m.vertices, m.triangles)); }

TEST(ScreenedPoisson, SphereConvergesAsTheGridShrinks) {
  const double R = 0.03, exact = 4.0 / 3.0 * M_PI * R * R * R;
  const Oriented s = balls({{Vec3(0.01, -0.02, 0.005), R}}, 20000);
  double previous = std::numeric_limits<double>::infinity();
  for (const double step : {0.004, 0.002, 0.001}) {
    ScreenedPoissonParams p;
    p.step = step;
    const ScreenedPoissonMesh m = screened_poisson_mesh(s.points, s.normals, s.areas, p);
    const double err = std::abs(volume_of(m) / exact - 1);
    std::printf("[screened] sphere R 30 mm, step %.0f mm: error %.4f %%, %d iterations, residual %.1e, %d levels\n", step * 1e3,
                100 * err, m.iterations, m.residual, m.levels);
    EXPECT_TRUE(mesh_is_watertight(m.triangles));
    EXPECT_LE(m.residual, p.tolerance);
    EXPECT_LT(err, previous);
    previous = err;
  }
  EXPECT_LT(previous, 0.003);
}

// Normals that are off (here turned halfway towards the direction from the shape's
// centre, as a wide normal estimator leaves them near a crease) bend the 2006
// equation's surface (screening 0) away from the samples; screening pulls it back
// through them.
TEST(ScreenedPoisson, ScreeningHoldsTheSurfaceToThePoints) {
  const double R = 0.02, d = 0.03, h = R - d / 2;
  const double exact = 2 * 4.0 / 3.0 * M_PI * R * R * R - 2 * M_PI * h * h * (3 * R - h) / 3;
  Oriented s = balls({{Vec3(-d / 2, 0, 0), R}, {Vec3(d / 2, 0, 0), R}}, 12000);
  for (Eigen::Index i = 0; i < s.normals.rows(); ++i) {
    s.normals.row(i) = (s.normals.row(i) + s.points.row(i).normalized()).normalized();
  }
  ScreenedPoissonParams p;
  p.step = 0.001;
  p.screening = 0;
  const ScreenedPoissonMesh plain = screened_poisson_mesh(s.points, s.normals, s.areas, p);
  p.screening = 4;
  const ScreenedPoissonMesh screened = screened_poisson_mesh(s.points, s.normals, s.areas, p);
  const double e_plain = volume_of(plain) / exact - 1, e_screened = volume_of(screened) / exact - 1;
  std::printf("[screened] two balls, bent normals: unscreened %+.3f %% (%d iterations, closed %d), screened %+.3f %% (%d)\n",
              100 * e_plain, plain.iterations, mesh_is_watertight(plain.triangles), 100 * e_screened, screened.iterations);
  EXPECT_LE(plain.residual, p.tolerance);  // the singular (unscreened) system is solved too
  EXPECT_TRUE(mesh_is_watertight(screened.triangles));
  EXPECT_LT(std::abs(e_screened), 0.5 * std::abs(e_plain));
}

// A sphere seen only above its equator (a side no camera saw): the inside runs out
// through the open side to the grid's boundary, where the mesh is capped, so it is
// still closed. A closed sphere needs no cap.
TEST(ScreenedPoisson, AnOpenSideIsCappedAtTheGridBoundary) {
  const Oriented whole = balls({{Vec3::Zero(), 0.02}}, 8000);
  std::vector<Eigen::Index> upper;
  for (Eigen::Index i = 0; i < whole.points.rows(); ++i) {
    if (whole.points(i, 2) > 0) upper.push_back(i);
  }
  const PointCloud points = whole.points(upper, Eigen::all), normals = whole.normals(upper, Eigen::all);
  const std::vector<double> areas(upper.size(), whole.areas[0]);
  const ScreenedPoissonMesh open = screened_poisson_mesh(points, normals, areas);
  const ScreenedPoissonMesh closed = screened_poisson_mesh(whole.points, whole.normals, whole.areas);
  std::printf("[screened] upper hemisphere: %zu boundary nodes capped, volume %.1f cm3 (ball %.1f)\n", open.capped,
              1e6 * volume_of(open), 1e6 * 4.0 / 3.0 * M_PI * 0.02 * 0.02 * 0.02);
  EXPECT_GT(open.capped, 0u);
  EXPECT_TRUE(mesh_is_watertight(open.triangles));
  EXPECT_EQ(closed.capped, 0u);
}

// A berry (R = 8 mm) on grids of 2 to 1 mm: the flat triangles cut its chords and
// miss ~9 rho^2 / 8R^2 of its volume, falling with the step squared; the curved surface
// through the same vertices (on the field's cubic level set) with the field's normals
// has not that error.
TEST(ScreenedPoisson, CurvedVolumeHasNotTheFlatTrianglesChordError) {
  const double R = 0.008, exact = 4.0 / 3.0 * M_PI * R * R * R;
  const Oriented s = balls({{Vec3(0.0003, -0.0002, 0.0001), R}}, 8000);
  double previous = -std::numeric_limits<double>::infinity();
  for (const double step : {0.002, 0.0015, 0.001}) {
    ScreenedPoissonParams p;
    p.step = step;
    const ScreenedPoissonMesh m = screened_poisson_mesh(s.points, s.normals, s.areas, p);
    ASSERT_EQ(m.normals.size(), m.vertices.size());
    const double flat = volume_of(m) / exact - 1, curved = (volume_of(m) + mesh_bulge_volume(m.vertices, m.normals, m.triangles)) / exact - 1;
    std::printf("[screened] berry R 8 mm, step %.1f mm: flat %+.3f %%, curved %+.3f %%\n", step * 1e3, 100 * flat, 100 * curved);
    EXPECT_LT(flat, 0);
    EXPECT_GT(flat, previous);  // the chord error falls with the step
    previous = flat;
    EXPECT_LT(std::abs(curved), 0.001);
    EXPECT_LT(std::abs(curved), 0.25 * std::abs(flat));
  }
}

// A torus (R = 30 mm, r = 10 mm) tiled by a 48 x 24 parametric grid with its exact
// normals: convex outside, saddle-shaped inside, where the edges bow inward.
TEST(MeshCurvedVolume, TorusWithExactNormals) {
  const double R = 0.03, r = 0.01, exact = 2 * M_PI * M_PI * R * r * r;
  const int nu = 48, nv = 24;
  std::vector<Vec3> v, n;
  std::vector<std::array<int, 3>> t;
  for (int i = 0; i < nu; ++i) {
    for (int j = 0; j < nv; ++j) {
      const double u = 2 * M_PI * i / nu, w = 2 * M_PI * j / nv;
      n.emplace_back(std::cos(w) * std::cos(u), std::cos(w) * std::sin(u), std::sin(w));
      v.push_back(Vec3(R * std::cos(u), R * std::sin(u), 0) + r * n.back());
      const int a = i * nv + j, b = ((i + 1) % nu) * nv + j, c = ((i + 1) % nu) * nv + (j + 1) % nv, d = i * nv + (j + 1) % nv;
      t.push_back({a, b, c});
      t.push_back({a, c, d});
    }
  }
  ASSERT_TRUE(mesh_is_watertight(t));
  if (mesh_signed_volume(v, t) < 0) {
    for (auto& f : t) std::swap(f[1], f[2]);
  }
  const double flat = mesh_signed_volume(v, t) / exact - 1, curved = (mesh_signed_volume(v, t) + mesh_bulge_volume(v, n, t)) / exact - 1;
  std::printf("[curved] torus 48 x 24: flat %+.3f %%, curved %+.4f %%\n", 100 * flat, 100 * curved);
  EXPECT_LT(flat, -0.005);
  EXPECT_LT(std::abs(curved), 0.02 * std::abs(flat));
  EXPECT_THROW(mesh_bulge_volume(v, std::vector<Vec3>(3), t), InputError);
}

TEST(ScreenedPoisson, SameInputSameBits) {
  const Oriented s = balls({{Vec3::Zero(), 0.02}}, 5000);
  const ScreenedPoissonMesh a = screened_poisson_mesh(s.points, s.normals, s.areas);
  const ScreenedPoissonMesh b = screened_poisson_mesh(s.points, s.normals, s.areas);
  EXPECT_EQ(a.triangles, b.triangles);
  ASSERT_EQ(a.vertices.size(), b.vertices.size());
  for (std::size_t i = 0; i < a.vertices.size(); ++i) EXPECT_EQ(a.vertices[i], b.vertices[i]);
}

TEST(ScreenedPoisson, BadInputGivesAClearError) {
  const Oriented s = balls({{Vec3::Zero(), 0.02}}, 2000);
  const auto message = [&](const PointCloud& pts, const PointCloud& nrm, const std::vector<double>& areas,
                           const ScreenedPoissonParams& p) -> std::string {
    try {
      screened_poisson_mesh(pts, nrm, areas, p);
    } catch (const InputError& e) {
      return e.what();
    }
    return "accepted";
  };
  EXPECT_NE(message(s.points, s.normals.topRows(10), s.areas, {}).find("one of each per point"), std::string::npos);
  PointCloud nan = s.normals;
  nan(5, 0) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(message(s.points, nan, s.areas, {}).find("normal"), std::string::npos);
  std::vector<double> zero = s.areas;
  zero[3] = 0;
  EXPECT_NE(message(s.points, s.normals, zero, {}).find("area"), std::string::npos);
  ScreenedPoissonParams p;
  p.step = 1e-5;
  EXPECT_NE(message(s.points, s.normals, s.areas, p).find("step"), std::string::npos);
  p.step = 2e-4;  // 1e8 nodes on a 4 cm ball scaled up to 2 m below
  PointCloud large = s.points * 50.0;
  EXPECT_NE(message(large, s.normals, s.areas, p).find("raise step"), std::string::npos);
  p = {};
  p.screening = -1;
  EXPECT_NE(message(s.points, s.normals, s.areas, p).find("screening"), std::string::npos);
  EXPECT_NE(message(PointCloud(2, 3), PointCloud(2, 3), {1, 1}, {}).find("screened_poisson"), std::string::npos);
}

// Contouring the signed distance of a sphere: a closed mesh whose volume converges
// to the ball's (the chords cut inside: slightly below).
TEST(GridContour, SphereDistanceGivesAClosedMesh) {
  const double R = 0.02, step = 0.001;
  const std::array<int, 3> n{51, 51, 51};
  const Vec3 origin = Vec3::Constant(-0.025);
  std::vector<double> f(static_cast<std::size_t>(n[0] * n[1] * n[2]));
  for (int z = 0, i = 0; z < n[2]; ++z)
    for (int y = 0; y < n[1]; ++y)
      for (int x = 0; x < n[0]; ++x, ++i) f[static_cast<std::size_t>(i)] = (origin + step * Vec3(x, y, z)).norm() - R;
  std::vector<Vec3> v;
  std::vector<std::array<int, 3>> t;
  contour_grid(f, n, origin, step, v, t);
  EXPECT_TRUE(mesh_is_watertight(t));
  const double exact = 4.0 / 3.0 * M_PI * R * R * R, got = mesh_signed_volume(v, t);
  EXPECT_GT(got, 0);  // outward
  EXPECT_NEAR(got / exact, 1, 0.005);
  // A ball cut by the grid's boundary leaves the surface open there.
  for (double& value : f) value -= 0.01;
  v.clear();
  t.clear();
  contour_grid(f, n, origin, step, v, t);
  EXPECT_FALSE(mesh_is_watertight(t));
}

TEST(MeshIsWatertight, ClosedOrientedManifoldOnly) {
  const std::vector<std::array<int, 3>> tet{{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}};
  EXPECT_TRUE(mesh_is_watertight(tet));
  EXPECT_FALSE(mesh_is_watertight({tet[0], tet[1], tet[2]}));  // a hole
  auto flipped = tet;
  std::swap(flipped[2][0], flipped[2][1]);
  EXPECT_FALSE(mesh_is_watertight(flipped));  // one face turned over
  auto doubled = tet;
  doubled.push_back(tet[0]);
  EXPECT_FALSE(mesh_is_watertight(doubled));  // a face twice
  EXPECT_FALSE(mesh_is_watertight({}));
  EXPECT_FALSE(mesh_is_watertight({{0, -1, 2}}));
}

}  // namespace
}  // namespace grapebench
