// CGAL's Poisson implicit function (Kazhdan et al. 2006 solved on a Delaunay
// refinement: CGAL's Poisson_reconstruction_function), contoured by marching
// tetrahedra on a regular grid (algorithms/volume/grid_contour.h). CGAL's own surface mesher
// is not used: its refinement queues order facets by memory address, so identical
// input gave different meshes from call to call. The implicit function is not wholly
// free of this either: on a 40k-point sphere one call in four gave grid values
// differing in the sixth digit (the volume in the ninth), with the same triangles.
// The screened solver (algorithms/volume/poisson_screened.h) is bit-for-bit repeatable.
// Kept in its own translation unit: CGAL's Poisson templates are heavy.
#pragma once

#include "algorithms/point_cloud.h"

#include <array>
#include <vector>

namespace grapebench {

struct CgalPoissonMesh {
  std::vector<Vec3> vertices;                 // m, in the frame of the input points
  std::vector<std::array<int, 3>> triangles;  // outward (the normals' side)
  std::size_t points_solved = 0;              // after the grid thinning
  std::size_t grid_nodes = 0;                 // implicit-function evaluations
  bool ok = false;                            // false: CGAL's solver failed
};

// points, normals: N x 3 (m; unit, outward). `cell` (m, 0: off) keeps one point per
// cell (CGAL's grid_simplify_point_set) before the solve; `step` (m) is the contouring
// grid's spacing. The grid covers the points' bounding box plus two steps.
CgalPoissonMesh cgal_poisson_mesh(const PointCloud& points, const PointCloud& normals, double cell, double step);

}  // namespace grapebench
