#include "algorithms/poisson_volume.h"

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

VolumeEstimate poisson_volume(const PointCloud& cloud, const PoissonParams& p) {
  require_solid(cloud, "poisson_volume");
  if (p.depth < 4 || p.depth > 12) throw InputError("poisson_volume: depth must lie in [4, 12]");
  if (!(p.samples_per_node >= 1 && p.samples_per_node <= 20)) throw InputError("poisson_volume: samples_per_node must lie in [1, 20]");
  if (!(p.scale >= 1 && p.scale <= 2)) throw InputError("poisson_volume: scale must lie in [1, 2]");
  const SmoothedCloud s = mls_smooth(cloud, p.mls);
  if (s.points.rows() < 4) throw InputError("poisson_volume: fewer than 4 points keep an MLS neighbourhood; raise mls.radius");
  const Eigen::RowVector3d centre = s.points.colwise().mean();
  auto in = pcl::make_shared<pcl::PointCloud<pcl::PointNormal>>();
  in->resize(static_cast<std::size_t>(s.points.rows()));
  for (Eigen::Index i = 0; i < s.points.rows(); ++i) {
    auto& q = (*in)[static_cast<std::size_t>(i)];
    const Eigen::RowVector3d x = s.points.row(i) - centre;
    q.x = static_cast<float>(x(0));
    q.y = static_cast<float>(x(1));
    q.z = static_cast<float>(x(2));
    q.normal_x = static_cast<float>(s.normals(i, 0));
    q.normal_y = static_cast<float>(s.normals(i, 1));
    q.normal_z = static_cast<float>(s.normals(i, 2));
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
  VolumeEstimate e;
  e.points_used = static_cast<std::size_t>(s.points.rows());
  // The reconstruction is about the centroid: the volume is summed there (precision),
  // the mesh is returned in the cloud's frame.
  std::vector<Vec3> local;
  for (const auto& v : verts) local.emplace_back(v.x, v.y, v.z);
  for (const auto& poly : mesh.polygons) {
    if (poly.vertices.size() != 3) continue;
    e.mesh_triangles.push_back({static_cast<int>(poly.vertices[0]), static_cast<int>(poly.vertices[1]),
                                static_cast<int>(poly.vertices[2])});
  }
  if (e.mesh_triangles.empty()) throw InputError("poisson_volume: the reconstruction is empty");
  for (const auto& v : local) e.mesh_vertices.push_back(v + centre.transpose());
  e.volume = std::abs(mesh_signed_volume(local, e.mesh_triangles));
  e.watertight = mesh_is_watertight(e.mesh_triangles);
  e.notes = std::to_string(e.mesh_triangles.size()) + " triangles" + (e.watertight ? "" : ", not watertight");
  return e;
}

}  // namespace grapebench
