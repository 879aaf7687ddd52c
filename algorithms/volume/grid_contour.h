// The zero level set of a function sampled on a regular grid, as a closed indexed
// triangle mesh: marching tetrahedra (each cube split into Kuhn's six tetrahedra).
// Shared by the Poisson solvers, which differ only in how they fill the grid.
#pragma once

#include "synth/types.h"

#include <array>
#include <vector>

namespace grapebench {

// values: n[0] x n[1] x n[2] samples, x fastest, negative inside; node (x, y, z) sits at
// origin + step * (x, y, z) (m). Appends the surface to vertices/triangles, each
// triangle facing outward (from the negative nodes to the others). The mesh is closed
// when every boundary node is non-negative.
void contour_grid(const std::vector<double>& values, const std::array<int, 3>& n, const Vec3& origin, double step,
                  std::vector<Vec3>& vertices, std::vector<std::array<int, 3>>& triangles);
void contour_grid(const std::vector<float>& values, const std::array<int, 3>& n, const Vec3& origin, double step,
                  std::vector<Vec3>& vertices, std::vector<std::array<int, 3>>& triangles);

}  // namespace grapebench
