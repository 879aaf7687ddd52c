// Screened Poisson surface reconstruction (Kazhdan & Hoppe 2013, "Screened Poisson
// surface reconstruction", ACM TOG 32(3)) on a regular grid, solved by conjugate
// gradients preconditioned with a geometric multigrid V-cycle, and contoured by
// marching tetrahedra (algorithms/volume/grid_contour.h), whose vertices are then moved onto
// the level set of the field's cubic interpolant.
//
// PB's other solvers (PCL, CGAL) have only Kazhdan et al.'s 2006 equation, whose
// level set drifts from the points wherever the normals are off: on bunch 7's surface
// with PB's MLS normals, +1.8 % unscreened against +0.3 % screened. The screening term
// pulls the level set through the points themselves; with screening 0 the equation
// is the 2006 one.
#pragma once

#include "algorithms/point_cloud.h"

#include <array>
#include <vector>

namespace grapebench {

struct ScreenedPoissonParams {
  // m, spacing of the finest grid, [2e-4, 0.05]; at most 5e7 nodes. 1 mm is a little
  // finer than Open3D's octree at depth 8 on a bunch (1.1-1.3 mm cells).
  double step = 0.001;
  // Dimensionless screening weight alpha, [0, 1e4]: the energy is
  // integral |grad chi - V|^2 + (alpha / step) * sum_i area_i * chi(p_i)^2
  // (Kazhdan & Hoppe 2013 Eq. 4, whose weight at depth d is alpha * 2^d: the same
  // resolution-independent balance). 0: the unscreened 2006 equation.
  double screening = 4;
  double tolerance = 1e-3;   // relative residual at which the solve stops, [1e-6, 0.1]
  int max_iterations = 100;  // conjugate-gradient iterations, [1, 1000]
};

struct ScreenedPoissonMesh {
  std::vector<Vec3> vertices;                 // m, in the frame of the input points
  std::vector<std::array<int, 3>> triangles;  // outward (the normals' side)
  std::vector<Vec3> normals;                  // per vertex: the field's unit gradient (outward)
  std::array<int, 3> grid{};                  // finest grid nodes per axis
  int levels = 0;                             // multigrid levels, finest included
  int iterations = 0;                         // conjugate-gradient iterations used
  double residual = 0;                        // final relative residual
  double iso = 0;                             // contoured value: the area-weighted mean of chi at the points
  std::size_t capped = 0;                     // grid-boundary nodes inside, set outside to close the mesh
};

// points, normals: N x 3 (m; unit, outward). areas: N, the surface area each point
// stands for (m2, > 0), which weights its normal (Kazhdan et al. 2006 Sec. 4.3) and its
// screening. The grid covers the points' bounding box plus four steps and some
// rounding. Where the points leave a side open, so that the inside reaches the grid's
// boundary, the mesh is capped on the boundary (`capped`): it is always closed. Throws InputError on mismatched sizes, non-finite or non-positive input, a
// parameter out of range, or a grid of more than 5e7 nodes.
ScreenedPoissonMesh screened_poisson_mesh(const PointCloud& points, const PointCloud& normals,
                                          const std::vector<double>& areas, const ScreenedPoissonParams& params = {});

}  // namespace grapebench
