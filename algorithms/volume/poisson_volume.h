// PB: Poisson surface reconstruction volume of seed 000 (Kazhdan et al. 2006; PCL's
// or CGAL's Poisson), from MLS normals, measured as the signed-tetrahedron sum (Eq. 11).
#pragma once

#include "algorithms/cloud/mls_smooth.h"
#include "algorithms/volume/poisson_screened.h"
#include "algorithms/volume_estimate.h"

namespace grapebench {

// Which Poisson solver reconstructs the surface. Seed 000 names Poisson (Kazhdan et
// al. 2006) without an implementation.
enum class PoissonSolver {
  Pcl,   // PCL's octree solver (PoissonRecon), depth-limited (the default)
  Cgal,  // CGAL's implicit function, contoured on a grid (algorithms/volume/poisson_cgal.h)
  Screened,  // screened Poisson (Kazhdan & Hoppe 2013) on a grid (algorithms/volume/poisson_screened.h)
};

struct PoissonParams {
  MlsParams mls;            // normals (seed 000: MLS before Poisson)
  // true: reconstruct from the MLS-projected points (seed 000 smooths and resamples
  // the registered cloud with MLS to remove ghosting); false: from the input points,
  // taking only the normals from MLS. Projection removes noise but moves a noise-free
  // surface (berries narrower than the MLS radius flatten).
  bool mls_positions = true;
  PoissonSolver solver = PoissonSolver::Pcl;
  // PCL:
  int depth = 8;            // octree depth, [4, 12]; 8 gives ~1 mm cells on a 0.25 m bunch
  double samples_per_node = 1.5;  // [1, 20]; more smooths noisy data
  double scale = 1.1;       // reconstruction cube / bounding cube, [1, 2]
  // CGAL:
  double cell = 0.003;      // m, one point per grid cell before the solve, [0, 0.05]; 0: all
  double step = 0.002;      // m, contouring grid spacing, [2e-4, 0.05]; at most 5e7 nodes
  // Screened: grid, screening weight and solve; each point's area is pi d^2 / k from
  // the distance d to its k-th neighbour.
  ScreenedPoissonParams screened;
  int area_neighbours = 10;  // k, [2, 100]
  // Screened only. false: the volume of the flat triangles (Eq. 11, seed 000's measure);
  // true: of the curved surface through their vertices with the field's normals
  // (mesh_signed_volume + mesh_bulge_volume), which has not the flat triangles' chord error.
  bool curved = false;
  // How the normals are turned outward (the harness's choice, not poisson_volume's):
  // centroid, seed 000's sign rule (mls_smooth); facing, each normal toward the camera
  // that saw its point (PCL's flipNormalTowardsViewpoint).
  enum class Orient { Centroid, Facing };
  Orient orient = Orient::Centroid;
};
// Scene keys of the `poisson` estimator; solver-specific keys are read only with their solver.
const ParamTable<PoissonParams>& poisson_param_table();

// Volume enclosed by the reconstructed mesh: sum over triangles of (a x b) . c / 6
// (Eq. 11). `watertight` is true when every edge has exactly two triangles with
// opposite orientations; otherwise the sum is still reported, and says so in notes.
// Throws InputError on degenerate clouds (fewer than 4 points, non-finite, coplanar).
// PCL's Poisson is not reentrant: concurrent calls with solver Pcl are serialised by a
// lock.
//
// MLS normals have no sign; mls_smooth points them away from the centroid, which is
// right only where the surface is star-shaped about it (the outer faces of a bunch,
// not the berry sides facing into it). `facing` (N x 3, one row per cloud row, any
// length; or empty) fixes the sign instead: each normal is turned to have a
// non-negative dot product with its point's row, e.g. the direction to the camera that
// saw the point (PCL's flipNormalTowardsViewpoint) or the normal of the mesh it was
// sampled from. Zero rows leave the centroid's choice.
VolumeEstimate poisson_volume(const PointCloud& cloud, const PoissonParams& params = {},
                              const PointCloud& facing = PointCloud());

// Signed volume of a triangle mesh (Eq. 11) and the closed-manifold test.
double mesh_signed_volume(const std::vector<Vec3>& vertices, const std::vector<std::array<int, 3>>& triangles);
bool mesh_is_watertight(const std::vector<std::array<int, 3>>& triangles);

// What the quadratic surface through a closed mesh's vertices with the given unit
// normals (per vertex, outward) encloses beyond its flat triangles (so that the curved
// surface's volume is mesh_signed_volume plus this): per triangle, its area times the
// mean of its edges' sagittas. An edge a-b of a surface with normals n_a, n_b
// bows out of its chord by (b - a) . (n_b - n_a) / 8 at its midpoint (exact on a circle:
// |b - a|^2 / 8R), and a quadratic that is 0 at the corners and s at the edge midpoints
// integrates to area * (s_ab + s_bc + s_ca) / 3 over the triangle. Flat triangles miss
// ~9 rho^2 / 8R^2 of a sphere of radius R (rho: their circumradius); this sum misses
// O(rho^4 / R^4). Concave edges (normals turning towards each other) bow inward.
double mesh_bulge_volume(const std::vector<Vec3>& vertices, const std::vector<Vec3>& normals,
                         const std::vector<std::array<int, 3>>& triangles);

}  // namespace grapebench
