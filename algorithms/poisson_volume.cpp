#include "algorithms/poisson_volume.h"

#include "algorithms/poisson_cgal.h"

#include <pcl/PolygonMesh.h>
#include <pcl/conversions.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/surface/poisson.h>

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <map>
#include <mutex>

namespace grapebench {

namespace {

// Points file descriptor 1 at /dev/null for its lifetime (also when an exception
// passes), flushing stdio on both sides.
struct StdoutSilenced {
  int saved = -1;
  StdoutSilenced() {
    std::fflush(stdout);
    saved = dup(1);
    const int devnull = open("/dev/null", O_WRONLY);
    if (saved >= 0 && devnull >= 0) dup2(devnull, 1);
    if (devnull >= 0) close(devnull);
  }
  ~StdoutSilenced() {
    std::fflush(stdout);
    if (saved >= 0) {
      dup2(saved, 1);
      close(saved);
    }
  }
  StdoutSilenced(const StdoutSilenced&) = delete;
  StdoutSilenced& operator=(const StdoutSilenced&) = delete;
};

}  // namespace

double mesh_signed_volume(const std::vector<Vec3>& v, const std::vector<std::array<int, 3>>& t) {
  double six = 0;
  for (const auto& f : t) six += v[static_cast<std::size_t>(f[0])].cross(v[static_cast<std::size_t>(f[1])]).dot(v[static_cast<std::size_t>(f[2])]);
  return six / 6;
}

bool mesh_is_watertight(const std::vector<std::array<int, 3>>& t) {
  if (t.empty()) return false;
  // Directed edge counts: closed and consistently oriented iff each directed edge
  // appears once and its reverse once.
  std::map<std::pair<int, int>, int> directed;
  for (const auto& f : t) {
    for (int k = 0; k < 3; ++k) ++directed[{f[static_cast<std::size_t>(k)], f[static_cast<std::size_t>((k + 1) % 3)]}];
  }
  for (const auto& [e, n] : directed) {
    if (n != 1) return false;
    const auto rev = directed.find({e.second, e.first});
    if (rev == directed.end() || rev->second != 1) return false;
  }
  return true;
}

namespace {

// PCL's octree Poisson on centred points; vertices in the centred frame.
void pcl_poisson_mesh(const PointCloud& centred, const PointCloud& normals, const PoissonParams& p,
                      std::vector<Vec3>& vertices, std::vector<std::array<int, 3>>& triangles) {
  auto in = pcl::make_shared<pcl::PointCloud<pcl::PointNormal>>();
  in->resize(static_cast<std::size_t>(centred.rows()));
  for (Eigen::Index i = 0; i < centred.rows(); ++i) {
    auto& q = (*in)[static_cast<std::size_t>(i)];
    q.x = static_cast<float>(centred(i, 0));
    q.y = static_cast<float>(centred(i, 1));
    q.z = static_cast<float>(centred(i, 2));
    q.normal_x = static_cast<float>(normals(i, 0));
    q.normal_y = static_cast<float>(normals(i, 1));
    q.normal_z = static_cast<float>(normals(i, 2));
  }
  pcl::Poisson<pcl::PointNormal> poisson;
  poisson.setInputCloud(in);
  poisson.setDepth(p.depth);
  poisson.setSamplesPerNode(static_cast<float>(p.samples_per_node));
  poisson.setScale(static_cast<float>(p.scale));
  poisson.setManifold(true);
  poisson.setOutputPolygons(false);
  poisson.setThreads(1);  // deterministic
  pcl::PolygonMesh mesh;
  {
    // PCL's Poisson (PoissonRecon 3rd party) keeps static state: two reconstructions
    // at once crash. Runs of the harness in parallel wait here.
    static std::mutex one_at_a_time;
    std::lock_guard<std::mutex> lock(one_at_a_time);
    // Its manifold repair prints "Vertex pair not in list" to stdout for every odd
    // cell; the watertight flag reports the outcome instead.
    const StdoutSilenced silenced;
    poisson.reconstruct(mesh);
  }
  pcl::PointCloud<pcl::PointXYZ> verts;
  pcl::fromPCLPointCloud2(mesh.cloud, verts);
  for (const auto& v : verts) vertices.emplace_back(v.x, v.y, v.z);
  for (const auto& poly : mesh.polygons) {
    if (poly.vertices.size() != 3) continue;
    triangles.push_back({static_cast<int>(poly.vertices[0]), static_cast<int>(poly.vertices[1]),
                         static_cast<int>(poly.vertices[2])});
  }
}

}  // namespace

VolumeEstimate poisson_volume(const PointCloud& cloud, const PoissonParams& p, const PointCloud& facing) {
  require_solid(cloud, "poisson_volume");
  if (facing.rows() != 0 && facing.rows() != cloud.rows()) {
    throw InputError("poisson_volume: facing has " + std::to_string(facing.rows()) + " rows for a cloud of " +
                     std::to_string(cloud.rows()) + " points; give one per point or none");
  }
  if (!facing.allFinite()) throw InputError("poisson_volume: facing has a non-finite entry");
  if (p.depth < 4 || p.depth > 12) throw InputError("poisson_volume: depth must lie in [4, 12]");
  if (!(p.samples_per_node >= 1 && p.samples_per_node <= 20)) throw InputError("poisson_volume: samples_per_node must lie in [1, 20]");
  if (!(p.scale >= 1 && p.scale <= 2)) throw InputError("poisson_volume: scale must lie in [1, 2]");
  check_range(p.cell, 0, 0.05, "poisson_volume", "cell", " m");
  check_range(p.step, 2e-4, 0.05, "poisson_volume", "step", " m");
  SmoothedCloud s = mls_smooth(cloud, p.mls);
  if (s.points.rows() < 4) throw InputError("poisson_volume: fewer than 4 points keep an MLS neighbourhood; raise mls.radius");
  Eigen::Index flipped = 0;
  if (facing.rows() != 0) {
    for (Eigen::Index i = 0; i < s.points.rows(); ++i) {
      if (s.normals.row(i).dot(facing.row(s.source[static_cast<std::size_t>(i)])) < 0) {
        s.normals.row(i) *= -1;
        ++flipped;
      }
    }
  }
  // The reconstruction runs about the centroid (precision); the volume is summed
  // there and the mesh returned in the cloud's frame.
  const Eigen::RowVector3d centre = s.points.colwise().mean();
  const PointCloud centred = s.points.rowwise() - centre;
  VolumeEstimate e;
  e.points_used = static_cast<std::size_t>(s.points.rows());
  std::vector<Vec3> local;
  std::string solver_note;
  if (p.solver == PoissonSolver::Cgal) {
    const Vec3 extent = (centred.colwise().maxCoeff() - centred.colwise().minCoeff()).transpose().array() + 4 * p.step;
    const double nodes = (extent / p.step).array().ceil().prod();
    if (nodes > 5e7) {
      throw InputError("poisson_volume: step = " + std::to_string(p.step) + " m gives " + std::to_string(nodes) +
                       " grid nodes on this cloud, more than 5e7; raise step");
    }
    CgalPoissonMesh m = cgal_poisson_mesh(centred, s.normals, p.cell, p.step);
    if (!m.ok) throw InputError("poisson_volume: CGAL's Poisson solver failed (inconsistent normals or too few points)");
    local = std::move(m.vertices);
    e.mesh_triangles = std::move(m.triangles);
    solver_note = "CGAL, " + std::to_string(m.points_solved) + " points solved, " + std::to_string(m.grid_nodes) + " grid nodes";
  } else {
    pcl_poisson_mesh(centred, s.normals, p, local, e.mesh_triangles);
    solver_note = "PCL depth " + std::to_string(p.depth);
  }
  if (e.mesh_triangles.empty()) throw InputError("poisson_volume: the reconstruction is empty");
  for (const auto& v : local) e.mesh_vertices.push_back(v + centre.transpose());
  e.volume = std::abs(mesh_signed_volume(local, e.mesh_triangles));
  e.watertight = mesh_is_watertight(e.mesh_triangles);
  if (facing.rows() != 0) solver_note += ", " + std::to_string(flipped) + " normals turned to face their row of facing";
  e.notes = solver_note + ", " + std::to_string(e.mesh_triangles.size()) + " triangles" +
            (e.watertight ? "" : ", not watertight");
  return e;
}

}  // namespace grapebench
