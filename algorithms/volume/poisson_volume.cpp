#include "algorithms/volume/poisson_volume.h"

#include "algorithms/pcl_cloud.h"
#include "algorithms/volume/poisson_cgal.h"

#include <pcl/PolygonMesh.h>
#include <pcl/kdtree/kdtree_flann.h>
#include <pcl/conversions.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/surface/poisson.h>

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdint>
#include <mutex>
#include <optional>

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

double mesh_bulge_volume(const std::vector<Vec3>& v, const std::vector<Vec3>& n, const std::vector<std::array<int, 3>>& t) {
  if (n.size() != v.size()) {
    throw InputError("mesh_bulge_volume: " + std::to_string(v.size()) + " vertices and " + std::to_string(n.size()) +
                     " normals; give one normal per vertex");
  }
  double bulge = 0;
  for (const auto& f : t) {
    const Vec3 &a = v[static_cast<std::size_t>(f[0])], &b = v[static_cast<std::size_t>(f[1])], &c = v[static_cast<std::size_t>(f[2])];
    const Vec3 &na = n[static_cast<std::size_t>(f[0])], &nb = n[static_cast<std::size_t>(f[1])], &nc = n[static_cast<std::size_t>(f[2])];
    // Twice the area, times the three edges' sagittas times 8.
    bulge += (b - a).cross(c - a).norm() * ((b - a).dot(nb - na) + (c - b).dot(nc - nb) + (a - c).dot(na - nc));
  }
  return bulge / 48;
}

bool mesh_is_watertight(const std::vector<std::array<int, 3>>& t) {
  if (t.empty()) return false;
  // Closed and consistently oriented iff each directed edge appears once and its
  // reverse once. The directed edges are grouped by their first vertex (counting
  // sort), so each check looks through one vertex's few neighbours.
  int vertices = 0;
  for (const auto& f : t) {
    for (const int v : f) {
      if (v < 0) return false;
      vertices = std::max(vertices, v + 1);
    }
  }
  std::vector<std::size_t> first(static_cast<std::size_t>(vertices) + 1, 0);
  for (const auto& f : t) {
    for (const int v : f) ++first[static_cast<std::size_t>(v) + 1];
  }
  for (std::size_t v = 0; v < static_cast<std::size_t>(vertices); ++v) first[v + 1] += first[v];
  std::vector<int> to(3 * t.size());
  std::vector<std::size_t> fill(first.begin(), first.end() - 1);
  for (const auto& f : t) {
    for (std::size_t k = 0; k < 3; ++k) to[fill[static_cast<std::size_t>(f[k])]++] = f[(k + 1) % 3];
  }
  const auto out_of = [&](int v) {
    return std::pair(to.begin() + static_cast<std::ptrdiff_t>(first[static_cast<std::size_t>(v)]),
                     to.begin() + static_cast<std::ptrdiff_t>(first[static_cast<std::size_t>(v) + 1]));
  };
  for (int v = 0; v < vertices; ++v) {
    const auto [b, e] = out_of(v);
    std::sort(b, e);
    if (std::adjacent_find(b, e) != e) return false;
  }
  for (int v = 0; v < vertices; ++v) {
    const auto [b, e] = out_of(v);
    for (auto w = b; w != e; ++w) {
      const auto [rb, re] = out_of(*w);
      if (!std::binary_search(rb, re, v)) return false;
    }
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

// The surface area each point stands for: pi d^2 / k, d the distance to its k-th
// neighbour (the disc holding k points at the local density).
std::vector<double> point_areas(const PointCloud& points, int k) {
  const auto cloud = to_pcl(points);
  pcl::KdTreeFLANN<pcl::PointXYZ> tree;
  tree.setInputCloud(cloud);
  const int want = std::min<int>(k + 1, static_cast<int>(points.rows()));  // the point itself comes first
  pcl::Indices nn;
  std::vector<float> d2;
  std::vector<double> areas(static_cast<std::size_t>(points.rows()));
  double smallest = 0;
  for (std::size_t i = 0; i < areas.size(); ++i) {
    tree.nearestKSearch((*cloud)[i], want, nn, d2);
    areas[i] = M_PI * static_cast<double>(d2.back()) / (want - 1);
    if (areas[i] > 0 && (smallest == 0 || areas[i] < smallest)) smallest = areas[i];
  }
  // Coincident points (k of them at one place) share the smallest area seen.
  for (double& a : areas) a = a > 0 ? a : (smallest > 0 ? smallest : 1e-12);
  return areas;
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
  check_range(p.area_neighbours, 2, 100, "poisson_volume", "area_neighbours");
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
  if (!p.mls_positions) {
    for (Eigen::Index i = 0; i < s.points.rows(); ++i) s.points.row(i) = cloud.row(s.source[static_cast<std::size_t>(i)]);
  }
  // The reconstruction runs about the centroid (precision); the volume is summed
  // there and the mesh returned in the cloud's frame.
  const Eigen::RowVector3d centre = s.points.colwise().mean();
  const PointCloud centred = s.points.rowwise() - centre;
  VolumeEstimate e;
  e.points_used = static_cast<std::size_t>(s.points.rows());
  std::vector<Vec3> local;
  std::string solver_note;
  std::optional<double> bulge;  // screened, curved: the curved surface's volume beyond the flat triangles'
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
  } else if (p.solver == PoissonSolver::Screened) {
    ScreenedPoissonMesh m = screened_poisson_mesh(centred, s.normals, point_areas(centred, p.area_neighbours), p.screened);
    if (p.curved) bulge = mesh_bulge_volume(m.vertices, m.normals, m.triangles);
    local = std::move(m.vertices);
    e.mesh_triangles = std::move(m.triangles);
    solver_note = "screened, grid " + std::to_string(m.grid[0]) + " x " + std::to_string(m.grid[1]) + " x " + std::to_string(m.grid[2]) +
                  ", " + std::to_string(m.levels) + " levels, " + std::to_string(m.iterations) + " iterations to residual " +
                  std::to_string(m.residual) +
                  (m.capped ? ", capped at " + std::to_string(m.capped) + " grid-boundary nodes (an open side)" : "");
  } else {
    pcl_poisson_mesh(centred, s.normals, p, local, e.mesh_triangles);
    solver_note = "PCL depth " + std::to_string(p.depth);
  }
  if (e.mesh_triangles.empty()) throw InputError("poisson_volume: the reconstruction is empty");
  for (const auto& v : local) e.mesh_vertices.push_back(v + centre.transpose());
  const double flat_signed = mesh_signed_volume(local, e.mesh_triangles);
  e.volume = std::abs(flat_signed + bulge.value_or(0));
  e.watertight = mesh_is_watertight(e.mesh_triangles);
  if (facing.rows() != 0) solver_note += ", " + std::to_string(flipped) + " normals turned to face their row of facing";
  if (bulge) {
    solver_note += ", volume of the curved surface through the vertices and normals (" +
                   std::to_string(std::abs(flat_signed) * 1e6) + " cm3 flat)";
  }
  e.notes = solver_note + ", " + std::to_string(e.mesh_triangles.size()) + " triangles" +
            (e.watertight ? "" : ", not watertight");
  return e;
}

const ParamTable<PoissonParams>& poisson_param_table() {
  using P = PoissonParams;
  const auto pcl = [](const P& p) { return p.solver == PoissonSolver::Pcl; };
  const auto cgal = [](const P& p) { return p.solver == PoissonSolver::Cgal; };
  const auto screened = [](const P& p) { return p.solver == PoissonSolver::Screened; };
  static const ParamTable<P> table =
      ParamTable<P>()
          .choice("solver", &P::solver,
                  {{"pcl", PoissonSolver::Pcl}, {"cgal", PoissonSolver::Cgal}, {"screened", PoissonSolver::Screened}},
                  "PCL's octree solver (Kazhdan 2006), CGAL's implicit function, or screened Poisson (Kazhdan 2013)")
          .integer("depth", "-", &P::depth, 4, 12, "octree depth; 8 gives ~1 mm cells on a 0.25 m bunch")
          .when("solver: pcl", pcl)
          .real("samples_per_node", "-", &P::samples_per_node, 1, 20, "more smooths noisy data")
          .when("solver: pcl", pcl)
          .real("scale", "-", &P::scale, 1, 2, "reconstruction cube / bounding cube")
          .when("solver: pcl", pcl)
          .real("step", "m", [](auto& p) -> auto& { return p.screened.step; }, 2e-4, 0.05, "grid step of the solve")
          .when("solver: screened", screened)
          .real("screening", "-", [](auto& p) -> auto& { return p.screened.screening; }, 0, 1e4,
                "screening weight (Kazhdan & Hoppe 2013: 4)")
          .when("solver: screened", screened)
          .real("tolerance", "-", [](auto& p) -> auto& { return p.screened.tolerance; }, 1e-6, 0.1,
                "relative residual at which the solve stops")
          .when("solver: screened", screened)
          .integer("area_neighbours", "count", &P::area_neighbours, 2, 100,
                   "k: a point's area is pi d^2 / k from the distance d to its k-th neighbour")
          .when("solver: screened", screened)
          .boolean("curved", &P::curved, "volume of the curved surface through the vertices (no chord error)")
          .when("solver: screened", screened)
          .real("cell", "m", &P::cell, 0, 0.05, "one point per grid cell before the solve; 0: all")
          .when("solver: cgal", cgal)
          .real("step", "m", &P::step, 2e-4, 0.05, "contouring grid spacing")
          .when("solver: cgal", cgal)
          .real("mls_radius", "m", [](auto& p) -> auto& { return p.mls.radius; }, 1e-4, 0.5,
                "MLS radius for the normals (seed 000: MLS before Poisson)")
          .integer("mls_order", "-", [](auto& p) -> auto& { return p.mls.polynomial_order; }, 0, 4,
                   "MLS polynomial order (seed 000 Eq. 3)")
          .boolean("mls_positions", &P::mls_positions, "reconstruct from the MLS-projected points (seed 000)")
          .choice("orient", &P::orient, {{"centroid", P::Orient::Centroid}, {"facing", P::Orient::Facing}},
                  "normals away from the centroid (seed 000) or toward each point's camera");
  return table;
}

}  // namespace grapebench
