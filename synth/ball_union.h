// Exact volume of a union of balls, and of a ball clipped by a convex polyhedron.
//
// The union of balls decomposes into the pieces B_i ∩ C_i, C_i the power cell of
// ball i (Edelsbrunner, "The union of balls and its dual shape", 1995). Only balls
// that overlap B_i can cut it: the radical plane of two disjoint balls misses both.
// Vol(B ∩ P) for a convex polyhedron P is a signed sum over P's faces of cones from
// the ball centre, each integrated in closed form (no sampling, no tessellation).
#pragma once

#include "synth/types.h"

#include <vector>

namespace grapebench {

// Half-space n·x <= offset, n unit.
struct HalfSpace {
  Vec3 n;
  double offset;
};

struct PolyFace {
  std::vector<Vec3> vertices;  // counter-clockwise seen from outside
  Vec3 normal;                 // unit, outward
  int tag = -1;                // which clip created it (-1 for the original body)
};

// A convex polyhedron as its faces. Clipping keeps it closed (each cut adds a cap).
struct ConvexPolyhedron {
  std::vector<PolyFace> faces;
  bool empty() const { return faces.empty(); }
};

ConvexPolyhedron make_box(const Vec3& centre, double half_side);
// Keeps the part with n·x <= offset; the new cap face gets `tag`.
void clip(ConvexPolyhedron& poly, const HalfSpace& h, int tag);
double polyhedron_volume(const ConvexPolyhedron& poly);

// Volume of ball(c, R) ∩ poly, closed form.
double ball_polyhedron_volume(const Vec3& c, double R, const ConvexPolyhedron& poly);

// The power-cell half-spaces of ball i against every ball that overlaps it, in
// coordinates relative to centres[i]. Returns false when ball i lies inside another
// ball's power cell entirely (coincident centres with a larger or earlier twin).
bool power_cell_halfspaces(const std::vector<Vec3>& centres, const std::vector<double>& radii,
                           int i, std::vector<HalfSpace>& out, std::vector<int>* neighbours = nullptr);

// Volume of ball i ∩ its power cell ∩ `extra` (relative to centres[i]).
double power_piece_volume(const std::vector<Vec3>& centres, const std::vector<double>& radii,
                          int i, const std::vector<HalfSpace>& extra = {});

double union_of_balls_volume(const std::vector<Vec3>& centres, const std::vector<double>& radii);

}  // namespace grapebench
