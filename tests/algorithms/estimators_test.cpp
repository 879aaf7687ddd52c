// Every estimator on analytic shapes with known answers (densely sampled surfaces,
// no noise), and on degenerate input.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <set>

#include "algorithms/volume/alpha_shape_volume.h"
#include "algorithms/volume/convex_hull_volume.h"
#include "algorithms/volume/cylinder_model_volume.h"
#include "algorithms/size/pca_box.h"
#include "algorithms/volume/poisson_volume.h"
#include "algorithms/external/python_estimator.h"
#include "algorithms/registry.h"
#include "algorithms/volume/voxel_volume.h"
#include "synth/rng.h"

namespace grapebench {
namespace {

// Unit-sphere samples with a 1e-7 tangential jitter: exactly cospherical points are
// the worst case of exact Delaunay predicates (slow), and scans never are.
std::vector<Vec3> fibonacci(int n) {
  std::vector<Vec3> p;
  Rng rng(17);
  const double g = M_PI * (3 - std::sqrt(5.0));
  for (int i = 0; i < n; ++i) {
    const double z = 1 - (2.0 * i + 1) / n, r = std::sqrt(1 - z * z);
    const Vec3 u(r * std::cos(g * i), r * std::sin(g * i), z);
    p.push_back((u + 1e-7 * Vec3(rng.normal(), rng.normal(), rng.normal())).normalized());
  }
  return p;
}

struct Shape {
  std::string name;
  std::vector<Vec3> surface;
  double volume;       // exact solid volume, m3
  double hull_volume;  // exact convex hull volume, m3
};

Shape sphere() {
  const double R = 0.05;
  std::vector<Vec3> p;
  for (const auto& u : fibonacci(40000)) p.push_back(R * u);
  const double v = 4.0 / 3.0 * M_PI * R * R * R;
  return {"sphere", p, v, v};
}

Shape ellipsoid() {
  const Vec3 abc(0.06, 0.04, 0.03);
  std::vector<Vec3> p;
  for (const auto& u : fibonacci(40000)) p.push_back(u.cwiseProduct(abc));
  const double v = 4.0 / 3.0 * M_PI * abc.prod();
  return {"ellipsoid", p, v, v};
}

Shape capped_cylinder() {
  const double r = 0.03, h = 0.12;
  std::vector<Vec3> p;
  // Dense rims (their extremes make GM exact), a coarser grid elsewhere (1.5 mm
  // spacing: fine enough to close VB's 2 mm shell).
  for (int k = 0; k < 3600; ++k) {
    const double a = 2 * M_PI * k / 3600;
    for (double z : {-h / 2, h / 2}) p.emplace_back(r * std::cos(a), r * std::sin(a), z);
  }
  const int around = 128, along = 80, rings = 20;
  for (int k = 0; k < around; ++k) {
    const double a = 2 * M_PI * (k + 0.5) / around;
    for (int j = 1; j < along; ++j) p.emplace_back(r * std::cos(a), r * std::sin(a), h * j / along - h / 2);
    for (int j = 1; j < rings; ++j) {
      for (double z : {-h / 2, h / 2}) p.emplace_back(r * j / rings * std::cos(a), r * j / rings * std::sin(a), z);
    }
  }
  const double v = M_PI * r * r * h;
  return {"capped_cylinder", p, v, v};
}

Shape two_spheres_of(int per_sphere) {
  const double R = 0.04, d = 0.06;  // centres at +-d/2 on x, overlapping
  std::vector<Vec3> p;
  for (double s : {-1.0, 1.0}) {
    const Vec3 c(s * d / 2, 0, 0), other(-s * d / 2, 0, 0);
    for (const auto& u : fibonacci(per_sphere)) {
      const Vec3 x = c + R * u;
      if ((x - other).norm() >= R) p.push_back(x);
    }
  }
  const double h = R - d / 2;  // cap height of each ball inside the other
  const double lens = 2 * M_PI * h * h * (3 * R - h) / 3;
  return {"two_spheres", p, 2 * 4.0 / 3.0 * M_PI * R * R * R - lens, 4.0 / 3.0 * M_PI * R * R * R + M_PI * R * R * d};
}
Shape two_spheres() { return two_spheres_of(40000); }

Shape box() {
  const Vec3 e(0.10, 0.06, 0.04);
  std::vector<Vec3> p;
  const int n = 100;
  for (int a = 0; a < 3; ++a) {
    const int b = (a + 1) % 3, c = (a + 2) % 3;
    for (double s : {-0.5, 0.5}) {
      for (int i = 0; i <= n; ++i)
        for (int j = 0; j <= n; ++j) {
          Vec3 x;
          x[a] = s * e[a];
          x[b] = (static_cast<double>(i) / n - 0.5) * e[b];
          x[c] = (static_cast<double>(j) / n - 0.5) * e[c];
          p.push_back(x);
        }
    }
  }
  return {"box", p, e.prod(), e.prod()};
}

// A shape's name and its maker: naming the 51 tests must not build their point sets
// (it did, in every test process: 1.3 s each in Release, 5 s under ASan).
struct ShapeMaker {
  std::string name;
  Shape (*make)();
  Shape operator()() const { return make(); }
};
const ShapeMaker kSphere{"sphere", sphere}, kEllipsoid{"ellipsoid", ellipsoid},
    kCappedCylinder{"capped_cylinder", capped_cylinder}, kTwoSpheres{"two_spheres", two_spheres}, kBox{"box", box};

// One estimator on one shape, built from its scene text through the registry (as a
// scene file would build it): the answer the shape's geometry gives for one of its
// quantities, and the documented tolerance (relative).
struct Case {
  std::string label;  // for the test name
  std::string scene;  // the estimator's scene mapping, e.g. "type: voxel\nvoxel_size: 0.002"
  ShapeMaker shape;
  Quantity quantity;
  std::function<double(const Shape&)> expected;
  double tolerance;
  bool must_close = false;  // the estimator's mesh or shell must be closed
  double jitter = 0;        // m: sd of a seeded jitter (exact grids are a Delaunay worst case)
};

// Runs the case's estimator as the harness does and returns the case's quantity.
double estimate(const Case& k, const Shape& s) {
  nlohmann::ordered_json params;
  const EstimatorBinding e = estimator_registry().create(ConfigNode::load_string(k.scene, k.label), params);
  PointCloud c = to_point_cloud(s.surface);
  Rng rng(3);
  for (Eigen::Index i = 0; k.jitter > 0 && i < c.rows(); ++i) {
    c.row(i) += k.jitter * Eigen::RowVector3d(rng.normal(), rng.normal(), rng.normal());
  }
  EstimatorInput input;
  input.points = std::move(c);
  const Estimate est = e.run(input);
  if (k.must_close && !est.watertight) throw std::runtime_error(k.label + " not closed: " + est.notes);
  for (const auto& [q, v] : est.values) {
    if (q == k.quantity) return v;
  }
  throw std::runtime_error(k.label + " gave no " + quantity_name(k.quantity));
}

void PrintTo(const Case& c, std::ostream* os) { *os << c.label << " on " << c.shape.name; }

class AnalyticShapes : public ::testing::TestWithParam<Case> {};

TEST_P(AnalyticShapes, EstimateMatchesKnownAnswer) {
  const Case& k = GetParam();
  if (k.label == "python" && !python_available()) GTEST_SKIP() << "built without Python (GRAPEBENCH_BUILD_PYTHON)";
  const Shape s = k.shape();
  ASSERT_EQ(s.name, k.shape.name);  // the name the test carries is the shape's
  const double got = estimate(k, s), want = k.expected(s);
  std::printf("[estimator] %-11s %-16s %-11s estimate %.6g, expected %.6g, error %+.3f %%\n", k.label.c_str(),
              s.name.c_str(), quantity_name(k.quantity), got, want, 100 * (got / want - 1));
  EXPECT_NEAR(got / want, 1.0, k.tolerance);
}

const auto hull = [](const Shape& s) { return s.hull_volume; };
const auto solid = [](const Shape& s) { return s.volume; };
// Sphere of radius R = 0.05 m (sphere()): its diameter, great circle and, since every
// coordinate of area-uniform points on a sphere is uniform in [-R, R] (Archimedes),
// the 2nd-98th percentile edge 0.96 * 2R (seed 003's alpha = 0.02).
constexpr double kR = 0.05;
const auto diameter = [](const Shape&) { return 2 * kR; };
const auto radius = [](const Shape&) { return kR; };
const auto great_circle = [](const Shape&) { return 2 * M_PI * kR; };
const auto percentile_edge = [](const Shape&) { return 0.96 * 2 * kR; };
const auto percentile_diagonal = [](const Shape&) { return std::sqrt(2.0) * 0.96 * 2 * kR; };
const auto percentile_volume = [](const Shape&) { return std::pow(0.96 * 2 * kR, 3); };
// capped_cylinder(): r = 0.03, h = 0.12.
const auto cylinder_height = [](const Shape&) { return 0.12; };
const auto cylinder_diameter = [](const Shape&) { return 0.06; };
const auto box_extent = [](int axis) { return [axis](const Shape&) { return Vec3(0.10, 0.06, 0.04)[axis]; }; };

const std::string kVB = "type: voxel\nvoxel_size: 0.002\nfill_interior: true";
const std::string kAS = "type: alpha_shape\nalpha: 1.0";
const std::string kPB = "type: poisson";
const std::string kPBCgal = "type: poisson\nsolver: cgal";
const std::string kPBScreened = "type: poisson\nsolver: screened";
const std::string kPBCurved = "type: poisson\nsolver: screened\ncurved: true";
// The Open3D example program (python3-open3d) through the external protocol.
const std::string kExternal = std::string("type: external\ncommand: [/usr/bin/python3, \"") + GRAPEBENCH_SOURCE_DIR +
                              "/scripts/external/open3d_estimator.py\"]";
// The same Open3D hull in-process (algorithms/external/python_estimator.h).
const std::string kPython = std::string("type: python\nmodule: open3d_estimator\npath: [\"") + GRAPEBENCH_SOURCE_DIR +
                            "/scripts/external\"]";
const std::string kCylinderFit = "type: cylinder_fit\nnormal_weight: 0\nmax_distance: 0.002";
constexpr Quantity V = Quantity::Volume;

std::vector<Case> cases() {
  return {
      // CH: the hull of the samples is inscribed in the true hull: below it by
      // O(spacing^2 / R); documented tolerance 0.5 % (sphere: the issue asks 2 %).
      {"CH", "type: convex_hull", kSphere, V, hull, 0.005},
      {"CH", "type: convex_hull", kEllipsoid, V, hull, 0.005},
      {"CH", "type: convex_hull", kCappedCylinder, V, hull, 0.005},
      {"CH", "type: convex_hull", kTwoSpheres, V, hull, 0.005},
      {"CH", "type: convex_hull", kBox, V, hull, 1e-9},
      // AS with alpha (1 m) far larger than the shape is its convex hull. A 1e-8 m
      // jitter breaks the exact grids' co-planarity, a Delaunay worst case.
      {"AS-large", kAS, kSphere, V, hull, 0.005, false, 1e-8},
      {"AS-large", kAS, kEllipsoid, V, hull, 0.005, false, 1e-8},
      {"AS-large", kAS, kCappedCylinder, V, hull, 0.005, false, 1e-8},
      {"AS-large", kAS, kTwoSpheres, V, hull, 0.005, false, 1e-8},
      {"AS-large", kAS, kBox, V, hull, 1e-6, false, 1e-8},
      // GM is exact on a cylinder standing on its axis (h > 2r).
      {"GM", "type: cylinder_model", kCappedCylinder, V, solid, 1e-6},
      // The PCA box is exact on an axis-aligned box, and gives a sphere's diameter.
      {"PCA-box-h", "type: pca_box", kBox, Quantity::Height, box_extent(0), 1e-9},
      {"PCA-box-l", "type: pca_box", kBox, Quantity::Length, box_extent(1), 1e-9},
      {"PCA-box-w", "type: pca_box", kBox, Quantity::Width, box_extent(2), 1e-9},
      {"PCA-box-h", "type: pca_box", kSphere, Quantity::Height, diameter, 0.001},
      // VB at 2 mm voxels: the filled shell overshoots by about half a voxel over
      // the surface (a full voxel on grid-aligned faces); documented tolerance 12 %.
      {"VB", kVB, kSphere, V, solid, 0.12, true},
      {"VB", kVB, kEllipsoid, V, solid, 0.12, true},
      {"VB", kVB, kCappedCylinder, V, solid, 0.12, true},
      {"VB", kVB, kTwoSpheres, V, solid, 0.12, true},
      {"VB", kVB, kBox, V, solid, 0.12, true},
      // PB: smooth closed surfaces within 2 % (the sphere figure); the
      // cylinder's rims and the spheres' crease are rounded off, 3 %.
      {"PB", kPB, kSphere, V, solid, 0.02, true},
      {"PB", kPB, kEllipsoid, V, solid, 0.02, true},
      {"PB", kPB, kCappedCylinder, V, solid, 0.03, true},
      {"PB", kPB, kTwoSpheres, V, solid, 0.03, true},
      // PB on CGAL's solver, contoured on a 2 mm grid: same tolerances.
      {"PB-CGAL", kPBCgal, kSphere, V, solid, 0.02, true},
      {"PB-CGAL", kPBCgal, kEllipsoid, V, solid, 0.02, true},
      {"PB-CGAL", kPBCgal, kCappedCylinder, V, solid, 0.03, true},
      {"PB-CGAL", kPBCgal, kTwoSpheres, V, solid, 0.03, true},
      // PB on the screened solver (1 mm grid), from the seed's MLS-projected points:
      // smooth surfaces within 0.5 % (measured: sphere +0.000 %, ellipsoid +0.025 %),
      // the cylinder's rims and the crease within 1.5 % (+0.66 %, -0.05 %).
      {"PB-screened", kPBScreened, kSphere, V, solid, 0.005, true},
      {"PB-screened", kPBScreened, kEllipsoid, V, solid, 0.005, true},
      {"PB-screened", kPBScreened, kCappedCylinder, V, solid, 0.015, true},
      {"PB-screened", kPBScreened, kTwoSpheres, V, solid, 0.015, true},
      // The same with the curved surface's volume (curved: true): same tolerances.
      {"PB-curved", kPBCurved, kSphere, V, solid, 0.005, true},
      {"PB-curved", kPBCurved, kEllipsoid, V, solid, 0.005, true},
      {"PB-curved", kPBCurved, kCappedCylinder, V, solid, 0.015, true},
      {"PB-curved", kPBCurved, kTwoSpheres, V, solid, 0.015, true},
      // Seed 003's size measures on the sphere (percentiles exact up to sampling).
      {"G_E", "type: percentile_box_edges", kSphere, Quantity::SizeMajor, percentile_edge, 0.002},
      {"G_E", "type: percentile_box_edges", kSphere, Quantity::SizeMinor, percentile_edge, 0.002},
      {"G_E", "type: percentile_box_edges", kSphere, V, percentile_volume, 0.006},
      {"G_D", "type: percentile_box_diagonals", kSphere, Quantity::SizeMajor, percentile_diagonal, 0.002},
      {"G_R", "type: ellipsoid_fit", kSphere, Quantity::SizeMajor, radius, 1e-4},
      {"G_R", "type: ellipsoid_fit", kSphere, Quantity::SizeMinor, radius, 1e-4},
      {"G_R-diam", "type: ellipsoid_fit\nmeasure: diameters", kSphere, Quantity::SizeMajor, diameter, 1e-4},
      // The cylinder fit on a cylinder: its height and diameter. Without the normal term
      // the rims (whose estimated normals mix side and cap) are inliers, so the height is
      // the cylinder's; 2 mm inliers keep the caps' inner rings out of the radius.
      {"G_C", kCylinderFit, kCappedCylinder, Quantity::SizeMajor, cylinder_height, 0.01},
      {"G_C", kCylinderFit, kCappedCylinder, Quantity::SizeMinor, cylinder_diameter, 0.01},
      // Seed 002's centre-section perimeters of a sphere: great circles.
      {"perimeters", "type: section_perimeters", kSphere, Quantity::PerimeterH, great_circle, 0.005},
      {"perimeters", "type: section_perimeters", kSphere, Quantity::PerimeterW, great_circle, 0.005},
      // The ellipsoid fit's volume is exact on a sphere and an ellipsoid.
      {"EV", "type: ellipsoid_volume", kSphere, V, solid, 1e-4},
      {"EV", "type: ellipsoid_volume", kEllipsoid, V, solid, 1e-4},
      // An external program (Open3D's hull) answers as CH does.
      {"external", kExternal, kSphere, V, hull, 0.005},
      {"python", kPython, kSphere, V, hull, 0.005},
  };
}

INSTANTIATE_TEST_SUITE_P(Seed000Estimators, AnalyticShapes, ::testing::ValuesIn(cases()), [](const auto& param_info) {
  std::string n =
      param_info.param.label + "_" + param_info.param.shape.name + "_" + quantity_name(param_info.param.quantity);
  for (auto& ch : n) ch = std::isalnum(static_cast<unsigned char>(ch)) ? ch : '_';
  return n + "_" + std::to_string(param_info.index);
});

// Adding an estimator to the registry without an analytic case fails here.
TEST(AnalyticShapes, EveryRegisteredEstimatorHasACase) {
  std::set<std::string> covered;
  for (const auto& k : cases()) {
    const auto n = ConfigNode::load_string(k.scene, k.label);
    covered.insert(n.get_string("type", ""));
  }
  // Estimators of a stereo pair have theirs on an analytic pair (luo2016_stereo_test.cpp);
  // classifiers of a labelled cloud on analytic shapes (dey2012_classification_test.cpp).
  for (const auto& type : estimator_registry().types()) {
    nlohmann::ordered_json params;
    if (type == "python" && !python_available()) continue;
    std::string yaml = "type: " + type + (type == "external" ? "\ncommand: [x]\nquantities: [volume]"
                                          : type == "python" ? "\nmodule: json\nfunction: dumps"
                                                             : "");
    if (estimator_registry().create(ConfigNode::load_string(yaml, "t.yaml"), params).input == "stereo_pair") {
      EXPECT_EQ(type, "luo2016_stereo") << "a new stereo estimator needs its analytic pair case";
      continue;
    }
    if (estimator_registry().create(ConfigNode::load_string(yaml, "t.yaml"), params).input == "image") {
      // On analytic images (luo2016_instances_test.cpp) and end to end beside an oracle
      // (Detection.OracleScores...).
      EXPECT_EQ(type, "luo2016_instances") << "a new image estimator needs its analytic image case";
      continue;
    }
    if (estimator_registry().create(ConfigNode::load_string(yaml, "t.yaml"), params).input == "labelled_cloud") {
      EXPECT_EQ(type, "dey2012_classification") << "a new classifier needs its analytic shapes case";
      continue;
    }
    EXPECT_TRUE(covered.count(type)) << type << " has no case";
  }
}

TEST(VoxelVolume, ConvergesAsTheVoxelShrinks) {
  const Shape s = sphere();
  const PointCloud c = to_point_cloud(s.surface);
  double previous = std::numeric_limits<double>::infinity();
  for (double k : {0.016, 0.008, 0.004, 0.002}) {
    const VolumeEstimate v = voxel_volume(c, {k, true, 2e8});
    const double err = std::abs(v.volume / s.volume - 1);
    std::printf("[voxel] edge %.0f mm: relative error %.4f\n", k * 1e3, err);
    EXPECT_TRUE(v.watertight);
    EXPECT_LT(err, previous);
    previous = err;
  }
  EXPECT_LT(previous, 0.08);
  // Voxels finer than the point spacing (0.9 mm here) leave the shell open: reported.
  const VolumeEstimate leaky = voxel_volume(c, {0.0005, true, 2e9});
  EXPECT_FALSE(leaky.watertight);
  EXPECT_NE(leaky.notes.find("not closed"), std::string::npos);
  // Counting only occupied voxels measures a shell, far below the solid volume.
  EXPECT_LT(voxel_volume(c, {0.002, false, 2e8}).volume, 0.3 * s.volume);
}

TEST(PoissonVolume, CgalSolverIsRepeatableClosedAndGuarded) {
  const PointCloud c = to_point_cloud(sphere().surface);
  PoissonParams p;
  p.solver = PoissonSolver::Cgal;
  p.step = 0.003;
  const VolumeEstimate a = poisson_volume(c, p), b = poisson_volume(c, p);
  EXPECT_TRUE(a.watertight) << a.notes;
  // CGAL's implicit function can differ in its last digits between calls (see
  // poisson_cgal.h); the contoured mesh keeps its connectivity.
  EXPECT_NEAR(a.volume / b.volume, 1, 1e-7);
  EXPECT_EQ(a.mesh_triangles, b.mesh_triangles);
  p.step = 2e-4;  // about 1e8 nodes on this shape
  try {
    poisson_volume(c, p);
    ADD_FAILURE() << "a grid above 5e7 nodes was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("raise step"), std::string::npos) << e.what();
  }
  p.step = 0.003;
  p.cell = 0.1;
  EXPECT_THROW(poisson_volume(c, p), InputError);  // cell outside [0, 0.05] m
}

// Two separate balls are not star-shaped about their centroid: pointing MLS normals
// away from it turns the inner half of each ball inside out. Given a facing direction
// per point (here the sampled surface's own normal), PB recovers the volume.
TEST(PoissonVolume, FacingFixesNormalsWhereTheCentroidCannot) {
  const double R = 0.02;
  std::vector<Vec3> points, outward;
  for (const double x : {-0.035, 0.035}) {
    for (const auto& u : fibonacci(6000)) {
      points.push_back(Vec3(x, 0, 0) + R * u);
      outward.push_back(u);
    }
  }
  const PointCloud c = to_point_cloud(points), facing = to_point_cloud(outward);
  const double exact = 2 * 4.0 / 3.0 * M_PI * R * R * R;
  for (const PoissonSolver solver : {PoissonSolver::Pcl, PoissonSolver::Cgal, PoissonSolver::Screened}) {
    PoissonParams p;
    p.solver = solver;
    p.mls.radius = 0.005;
    p.depth = 7;
    p.step = 0.0015;
    p.screened.step = 0.0015;
    const VolumeEstimate centroid = poisson_volume(c, p), faced = poisson_volume(c, p, facing);
    EXPECT_GT(std::abs(centroid.volume / exact - 1), 0.1) << centroid.notes;
    EXPECT_NEAR(faced.volume / exact, 1, 0.02) << faced.notes;
    EXPECT_TRUE(faced.watertight) << faced.notes;
    EXPECT_NE(faced.notes.find("normals turned"), std::string::npos) << faced.notes;
  }
  EXPECT_THROW(poisson_volume(c, {}, facing.topRows(10)), InputError);  // one row per point
  PointCloud bad = facing;
  bad(3, 1) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(poisson_volume(c, {}, bad), InputError);
}

TEST(AlphaShape, SmallerAlphaCarvesTheConcavityOfTwoSpheres) {
  // 10000 points a sphere (1.4 mm apart): the orderings below hold at any density
  // finer than the alpha values (40000 cost 61 s under ASan).
  const Shape s = two_spheres_of(10000);
  const PointCloud c = to_point_cloud(s.surface);
  // Above the sphere radius the alpha balls fill each berry-like ball; they cannot
  // enter the crevice where the balls meet, so the volume lies between the union and
  // the hull and grows with alpha towards the hull.
  double previous = s.volume, tight = 0;
  for (double a : {0.045, 0.1, 1.0}) {
    const VolumeEstimate v = alpha_shape_volume(c, {a});
    std::printf("[alpha] two spheres (R 0.04 m): alpha %.3f m -> %.2f cm3 (union %.2f, hull %.2f), watertight %d\n", a,
                v.volume * 1e6, s.volume * 1e6, s.hull_volume * 1e6, v.watertight);
    EXPECT_GT(v.volume, previous);
    EXPECT_LE(v.volume, s.hull_volume);
    EXPECT_TRUE(v.watertight);
    if (a == 0.045) tight = v.volume;
    previous = v.volume;
  }
  EXPECT_EQ(alpha_shape_volume(c, {0.045}).volume, tight);  // same input, same bits
  // Below the ball radius the complex of a surface sampling stays hollow.
  EXPECT_LT(alpha_shape_volume(c, {0.03}).volume, 0.2 * s.volume);
}

TEST(PcaBox, AxesAndExtentsOfARotatedBox) {
  const Shape s = box();
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  std::vector<Vec3> p;
  for (const auto& x : s.surface) p.push_back(R * x + Vec3(0.3, -0.2, 1.0));
  const PcaBox b = pca_box(to_point_cloud(p));
  EXPECT_NEAR(b.height, 0.10, 1e-9);
  EXPECT_NEAR(b.length, 0.06, 1e-9);
  EXPECT_NEAR(b.width, 0.04, 1e-9);
  EXPECT_NEAR(std::abs(b.axes.col(0).dot(R.col(0))), 1.0, 1e-9);
}

TEST(Estimators, DegenerateInputGivesAClearError) {
  const PointCloud empty(0, 3);
  PointCloud three(3, 3);
  three << 0, 0, 0, 1, 0, 0, 0, 1, 0;
  PointCloud flat(100, 3);
  for (int i = 0; i < 100; ++i) flat.row(i) << std::cos(i), std::sin(i), 0.0;
  PointCloud nan = flat;
  nan(7, 2) = std::numeric_limits<double>::quiet_NaN();
  const std::vector<std::pair<std::string, std::function<void(const PointCloud&)>>> estimators = {
      {"CH", [](const PointCloud& c) { convex_hull_volume(c); }},
      {"GM", [](const PointCloud& c) { cylinder_model_volume(c); }},
      {"VB", [](const PointCloud& c) { voxel_volume(c); }},
      {"PCA-box", [](const PointCloud& c) { pca_box(c); }},
      {"AS", [](const PointCloud& c) { alpha_shape_volume(c); }},
      {"PB-CGAL",
       [](const PointCloud& c) {
         PoissonParams p;
         p.solver = PoissonSolver::Cgal;
         poisson_volume(c, p);
       }},
      {"PB-screened",
       [](const PointCloud& c) {
         PoissonParams p;
         p.solver = PoissonSolver::Screened;
         poisson_volume(c, p);
       }},
  };
  for (const auto& [name, run] : estimators) {
    for (const PointCloud* c : std::initializer_list<const PointCloud*>{&empty, &nan}) {
      EXPECT_THROW(run(*c), InputError) << name;
    }
    if (name != "PCA-box") {
      EXPECT_THROW(run(three), InputError) << name;
      EXPECT_THROW(run(flat), InputError) << name;  // coplanar: no volume
    }
  }
  try {
    convex_hull_volume(nan);
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("point 7"), std::string::npos) << e.what();
  }
  EXPECT_THROW(voxel_volume(flat, {1e-6, true, 2e8}), InputError);  // voxel size out of range
  EXPECT_THROW(voxel_volume(flat, {1e-4, true, 1e3}), InputError);  // grid too large
}

}  // namespace
}  // namespace grapebench
