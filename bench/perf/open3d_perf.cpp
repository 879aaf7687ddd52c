// Google Benchmark: grapebench's estimators beside the same operation in Open3D
// (Debian's libopen3d-dev), on one 50,000-point registered bunch, in the same run.
// Open3D parallelises with OpenMP: run with OMP_NUM_THREADS=1 to compare one core
// with one core (grapebench's estimators are single-threaded).
#include "algorithms/alpha_shape_volume.h"
#include "algorithms/convex_hull_volume.h"
#include "algorithms/filters.h"
#include "algorithms/mls_smooth.h"
#include "algorithms/poisson_volume.h"
#include "algorithms/registration.h"
#include "algorithms/voxel_volume.h"
#include "sensors/kinect_v2.h"
#include "sensors/scan.h"
#include "sensors/visibility_hull.h"
#include "synth/generate.h"
#include "synth/ground_truth.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/compute_average_spacing.h>
#include <CGAL/poisson_surface_reconstruction.h>
#include <benchmark/benchmark.h>
#include <open3d/geometry/PointCloud.h>
#include <open3d/geometry/TriangleMesh.h>
#include <open3d/geometry/VoxelGrid.h>
#include <open3d/pipelines/registration/Registration.h>
#include <open3d/utility/Logging.h>

#include <cstdio>

namespace {

using namespace grapebench;

constexpr Eigen::Index kPoints = 50000;

struct Registered {
  PointCloud cloud;  // kPoints x 3, m
  std::shared_ptr<open3d::geometry::PointCloud> o3d;
  double true_volume = 0;
  Bunch bunch;                  // the scanned bunch
  std::vector<Camera> cameras;  // the 24 views
};

// 24 Kinect v2 views at 15 deg (seed 000's rig at twice the views) merged with the true
// poses, bunch points only, thinned by a fixed stride to exactly kPoints.
const Registered& registered() {
  static const Registered r = [] {
    open3d::utility::SetVerbosityLevel(open3d::utility::VerbosityLevel::Error);
    const BunchParams p = preset("table-red");
    const Bunch b = generate_bunch(p, 7);
    const RayScene scene(b);
    TurntableParams tp;
    tp.views = 24;
    tp.step_deg = 15;
    const Scan scan = scan_bunch(scene, KinectV2(KinectV2Params{}), *make_turntable(tp), BackgroundSpec{}, 1);
    std::vector<Vec3> all;
    for (const auto& v : scan.views) {
      for (const auto& q : v.cloud.bunch_points()) all.push_back(v.rig.pose * q);
    }
    if (static_cast<Eigen::Index>(all.size()) < kPoints) {
      std::fprintf(stderr, "only %zu points\n", all.size());
      std::exit(1);
    }
    std::vector<Vec3> pts;
    const double stride = static_cast<double>(all.size()) / kPoints;
    for (Eigen::Index i = 0; i < kPoints; ++i) pts.push_back(all[static_cast<std::size_t>(static_cast<double>(i) * stride)]);
    Registered out;
    out.cloud = to_point_cloud(pts);
    out.o3d = std::make_shared<open3d::geometry::PointCloud>(pts);
    out.true_volume = compute_ground_truth(b, p.density).volume.solid;
    out.bunch = b;
    for (const auto& v : scan.views) out.cameras.push_back(v.camera);
    std::printf("registered bunch: %lld points (of %zu), true volume %.1f cm3\n", static_cast<long long>(kPoints), all.size(),
                out.true_volume * 1e6);
    return out;
  }();
  return r;
}

// Signed-tetrahedron volume of a triangle mesh (seed 000 Eq. 11), the same sum for
// both libraries; Open3D's GetVolume() refuses meshes that are not watertight.
double signed_volume(const open3d::geometry::TriangleMesh& m) {
  double v = 0;
  for (const auto& t : m.triangles_) v += m.vertices_[t(0)].dot(m.vertices_[t(1)].cross(m.vertices_[t(2)])) / 6;
  return std::abs(v);
}

void report(benchmark::State& state, double volume, bool watertight) {
  state.counters["volume_cm3"] = volume * 1e6;
  state.counters["error_pct"] = 100 * (volume / registered().true_volume - 1);
  state.counters["watertight"] = watertight ? 1 : 0;
}

// Times make_mesh() and reports the volume of the last mesh it made.
template <class F>
void open3d_mesh_volume(benchmark::State& state, F make_mesh) {
  std::shared_ptr<open3d::geometry::TriangleMesh> mesh;
  for (auto _ : state) mesh = make_mesh();
  report(state, signed_volume(*mesh), mesh->IsWatertight());
}

// ---- convex hull
void BM_CH_grapebench(benchmark::State& s) {
  VolumeEstimate v;
  for (auto _ : s) benchmark::DoNotOptimize(v = convex_hull_volume(registered().cloud));
  report(s, v.volume, v.watertight);
}
void BM_CH_open3d(benchmark::State& s) {
  open3d_mesh_volume(s, [] { return std::get<0>(registered().o3d->ComputeConvexHull()); });
}

// ---- alpha shape, alpha = 25 mm (a radius in both libraries)
void BM_AS_grapebench(benchmark::State& s) {
  VolumeEstimate v;
  for (auto _ : s) benchmark::DoNotOptimize(v = alpha_shape_volume(registered().cloud, {0.025}));
  report(s, v.volume, v.watertight);
}
void BM_AS_open3d(benchmark::State& s) {
  open3d_mesh_volume(s, [] { return open3d::geometry::TriangleMesh::CreateFromPointCloudAlphaShape(*registered().o3d, 0.025); });
}

// ---- Poisson, depth 8, normals included in the time (PB: MLS; Open3D: PCA normals
// from 30 neighbours within 10 mm, oriented away from the centroid like PB's)
void BM_PB_grapebench(benchmark::State& s) {
  VolumeEstimate v;
  for (auto _ : s) benchmark::DoNotOptimize(v = poisson_volume(registered().cloud));
  report(s, v.volume, v.watertight);
}
// PB on CGAL's implicit function, contoured on a 2 mm grid (solver: cgal).
void BM_PB_grapebench_cgal(benchmark::State& s) {
  PoissonParams p;
  p.solver = PoissonSolver::Cgal;
  VolumeEstimate v;
  for (auto _ : s) benchmark::DoNotOptimize(v = poisson_volume(registered().cloud, p));
  report(s, v.volume, v.watertight);
}
void BM_PB_open3d(benchmark::State& s) {
  open3d_mesh_volume(s, [] {
    open3d::geometry::PointCloud pcd = *registered().o3d;
    pcd.EstimateNormals(open3d::geometry::KDTreeSearchParamHybrid(0.01, 30));
    const Eigen::Vector3d c = pcd.GetCenter();
    for (std::size_t i = 0; i < pcd.points_.size(); ++i) {
      if (pcd.normals_[i].dot(pcd.points_[i] - c) < 0) pcd.normals_[i] = -pcd.normals_[i];
    }
    return std::get<0>(open3d::geometry::TriangleMesh::CreateFromPointCloudPoisson(pcd, 8, 0, 1.1f, false, 1));
  });
}

// The third Poisson of the brief's reference figures: CGAL's, from the same MLS
// normals as PB, at CGAL's default meshing criteria and the points' mean spacing.
void BM_PB_cgal(benchmark::State& s) {
  using K = CGAL::Exact_predicates_inexact_constructions_kernel;
  using Pwn = std::pair<K::Point_3, K::Vector_3>;
  double v = 0;
  bool closed = false;
  for (auto _ : s) {
    const SmoothedCloud m = mls_smooth(registered().cloud);
    std::vector<Pwn> pts;
    for (Eigen::Index i = 0; i < m.points.rows(); ++i) {
      pts.emplace_back(K::Point_3(m.points(i, 0), m.points(i, 1), m.points(i, 2)),
                       K::Vector_3(m.normals(i, 0), m.normals(i, 1), m.normals(i, 2)));
    }
    const auto point_map = CGAL::First_of_pair_property_map<Pwn>();
    const double spacing =
        CGAL::compute_average_spacing<CGAL::Sequential_tag>(pts, 6, CGAL::parameters::point_map(point_map));
    CGAL::Surface_mesh<K::Point_3> mesh;
    if (!CGAL::poisson_surface_reconstruction_delaunay(pts.begin(), pts.end(), point_map,
                                                      CGAL::Second_of_pair_property_map<Pwn>(), mesh, spacing)) {
      s.SkipWithError("CGAL Poisson failed");
      return;
    }
    closed = CGAL::is_closed(mesh);
    v = closed ? std::abs(CGAL::Polygon_mesh_processing::volume(mesh)) : 0;
  }
  report(s, v, closed);
}

// The floor under every volume above: the visibility hull of the 24 views (space no
// camera sees, at 1 mm samples), which no reconstruction from them can tell from the
// solid. Its error is the least overestimate of an estimator that invents no geometry.
void BM_floor_visibility_hull(benchmark::State& s) {
  const RayScene scene(registered().bunch);
  VisibilityHull h;
  for (auto _ : s) benchmark::DoNotOptimize(&(h = visibility_hull(scene, registered().cameras, {0.001, 0.003})));
  report(s, h.volume, true);
}

// ---- voxel grid downsampling, 5 mm
void BM_VoxelGrid_grapebench(benchmark::State& s) {
  FilteredCloud f;
  for (auto _ : s) benchmark::DoNotOptimize(f = voxel_grid(registered().cloud, {0.005}));
  s.counters["voxels"] = static_cast<double>(f.points.rows());
}
void BM_VoxelGrid_open3d(benchmark::State& s) {
  std::size_t n = 0;
  for (auto _ : s) benchmark::DoNotOptimize(n = registered().o3d->VoxelDownSample(0.005)->points_.size());
  s.counters["voxels"] = static_cast<double>(n);
}
// VB (seed 000 Eq. 7) fills the interior; Open3D's voxel grid holds only the voxels
// the points fall in, so its "volume" is a shell.
void BM_VB_grapebench(benchmark::State& s) {
  VolumeEstimate v;
  for (auto _ : s) benchmark::DoNotOptimize(v = voxel_volume(registered().cloud, {0.005, true, 2e8}));
  report(s, v.volume, v.watertight);
}
void BM_VB_open3d(benchmark::State& s) {
  double v = 0;
  for (auto _ : s) {
    auto grid = open3d::geometry::VoxelGrid::CreateFromPointCloud(*registered().o3d, 0.005);
    v = static_cast<double>(grid->voxels_.size()) * 0.005 * 0.005 * 0.005;
  }
  report(s, v, false);
}

// ---- ICP: the cloud moved by 3 deg and 4 mm, point to point, 10 mm gate, 50 iterations
struct Moved {
  PointCloud source;
  std::shared_ptr<open3d::geometry::PointCloud> o3d;
  Eigen::Isometry3d truth;  // source -> target
};
const Moved& moved() {
  static const Moved m = [] {
    const PointCloud& target = registered().cloud;
    Eigen::Isometry3d motion = Eigen::Isometry3d::Identity();
    const Vec3 c = target.colwise().mean().transpose();
    motion.linear() = Eigen::AngleAxisd(3 * M_PI / 180, Vec3(0.3, 1, 0.2).normalized()).toRotationMatrix();
    motion.translation() = c - motion.linear() * c + Vec3(0.004, -0.002, 0.001);
    Moved out;
    out.source = (target * motion.linear().transpose()).rowwise() + motion.translation().transpose();
    std::vector<Vec3> pts;
    for (Eigen::Index i = 0; i < out.source.rows(); ++i) pts.push_back(out.source.row(i).transpose());
    out.o3d = std::make_shared<open3d::geometry::PointCloud>(pts);
    out.truth = motion.inverse();
    return out;
  }();
  return m;
}
void BM_ICP_grapebench(benchmark::State& s) {
  IcpParams p;
  p.max_correspondence_distance = 0.01;
  p.max_iterations = 50;
  IcpResult r;
  for (auto _ : s) r = icp_align(moved().source, registered().cloud, Eigen::Isometry3d::Identity(), p);
  s.counters["rotation_error_deg"] = rotation_error_deg(r.transform, moved().truth);
  s.counters["translation_error_mm"] = 1e3 * centroid_displacement(r.transform, moved().truth, moved().source);
}
void BM_ICP_open3d(benchmark::State& s) {
  namespace reg = open3d::pipelines::registration;
  reg::RegistrationResult r;
  for (auto _ : s) {
    r = reg::RegistrationICP(*moved().o3d, *registered().o3d, 0.01, Eigen::Matrix4d::Identity(),
                             reg::TransformationEstimationPointToPoint(), reg::ICPConvergenceCriteria(1e-6, 1e-6, 50));
  }
  const Eigen::Isometry3d t(r.transformation_);
  s.counters["rotation_error_deg"] = rotation_error_deg(t, moved().truth);
  s.counters["translation_error_mm"] = 1e3 * centroid_displacement(t, moved().truth, moved().source);
}

}  // namespace

BENCHMARK(BM_CH_grapebench)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_CH_open3d)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_AS_grapebench)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_AS_open3d)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_PB_grapebench)->Unit(benchmark::kMillisecond)->Iterations(2);
BENCHMARK(BM_PB_grapebench_cgal)->Unit(benchmark::kMillisecond)->Iterations(2);
BENCHMARK(BM_PB_open3d)->Unit(benchmark::kMillisecond)->Iterations(2);
BENCHMARK(BM_PB_cgal)->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK(BM_floor_visibility_hull)->Unit(benchmark::kMillisecond)->Iterations(2);
BENCHMARK(BM_VoxelGrid_grapebench)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_VoxelGrid_open3d)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_VB_grapebench)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_VB_open3d)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ICP_grapebench)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ICP_open3d)->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
