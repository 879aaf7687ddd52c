// Geometry of stems (finite cylinders) and their exact overlaps.
#pragma once

#include "synth/types.h"

namespace grapebench {

double point_segment_distance(const Vec3& p, const Vec3& a, const Vec3& b);
double segment_segment_distance(const Vec3& p0, const Vec3& p1, const Vec3& q0, const Vec3& q1);
bool inside_stem(const Stem& s, const Vec3& x);

// Distance t >= 0 along the unit direction d at which the line p + t d leaves the
// finite cylinder `s`; p must be inside. Closed form: the slab of the two end caps
// and the quadratic of the lateral surface.
double exit_distance(const Stem& s, const Vec3& p, const Vec3& d);

// Volume of child ∩ parent for a child that starts on the parent's axis, strictly
// inside it: the child's cross-section disk is swept along the child's axis and
// each line contributes its closed-form length inside the parent, integrated by
// adaptive Gauss-Kronrod quadrature (relative error below 1e-10 of the term).
double junction_overlap_volume(const Stem& child, const Stem& parent);

// Volume of a pedicel inside the berry it carries, in closed form. The pedicel's
// axis passes through the berry centre, it starts outside the berry and ends inside
// it no deeper than the plane where its rim meets the sphere on the far side:
//   V = pi r^2 s_E + (2 pi / 3) (R^3 - (R^2 - r^2)^(3/2)),
// with s_E the signed axial position of the pedicel end from the berry centre.
// Throws InputError when the configuration breaks those conditions.
double pedicel_in_berry_volume(const Stem& pedicel, const Berry& berry);

// Axial position (from the berry centre, along the pedicel direction) of the plane
// through the circle where the pedicel's rim enters the berry: -sqrt(R^2 - r^2).
double pedicel_entry_offset(const Stem& pedicel, const Berry& berry);

// An orthonormal pair perpendicular to the unit vector d (deterministic).
void perpendicular_basis(const Vec3& d, Vec3& e1, Vec3& e2);

}  // namespace grapebench
