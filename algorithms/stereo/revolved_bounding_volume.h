// Seed 001's bounding volume (Luo et al. 2016, Sect. 2.2.4): the cutting point as the
// origin and the vertical through it as the cluster's axis; each berry point's distance
// from the axis l_j (Eq. 9) and its height y_j below the origin; the convex section of
// (l, y) (the "maximum section", Fig. 7c) revolved 360 degrees about the axis.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "synth/types.h"

namespace grapebench {

struct RevolvedBoundingVolume {
  double volume = 0;                     // m3, of the revolved section
  double height = 0;                     // m, vertical extent of the section
  double max_diameter = 0;               // m, 2 max l_j
  std::vector<Eigen::Vector2d> section;  // (l, y) convex polygon, counter-clockwise, m
};

// origin: the cutting point; points: the berries (front-surface centres), both in a
// frame whose y axis points down the vertical (the left camera's, level), m. The
// section is the convex hull of the origin, the points and their feet on the axis, so
// it reaches the axis at every height it spans; its volume by Pappus' theorem (2 pi x
// area x centroid distance from the axis), exact for the polygon.
RevolvedBoundingVolume revolved_bounding_volume(const Vec3& origin, const std::vector<Vec3>& points);

}  // namespace grapebench
