// Hobby's smooth interpolating spline through a closed polygon (Hobby 1986, cited by
// seed 002 for Eq. 11), and its length by arc-length quadrature (seed 002 Eq. 12).
#pragma once

#include <Eigen/Core>

#include <array>
#include <vector>

namespace grapebench {

using Vec2 = Eigen::Vector2d;

// One cubic Bezier segment per knot: knot k to knot k+1 (cyclic). B(t) of seed 002
// Eq. 11 with P0 = knot k, P1/P2 the control points, P3 = knot k+1.
struct ClosedHobbySpline {
  std::vector<std::array<Vec2, 4>> segments;
};

// Knots in order around the curve (either orientation), at least 3, no two equal in a
// row. tension in [0.75, 4] (1: Hobby's and MetaPost's default). Throws InputError for
// fewer than 3 knots, repeated consecutive knots or a bad tension.
ClosedHobbySpline closed_hobby_spline(const std::vector<Vec2>& knots, double tension = 1.0);

// Arc length, m: 16-point Gauss-Legendre on each half of every segment.
double spline_length(const ClosedHobbySpline& spline);

}  // namespace grapebench
