// Perimeters of the three sections through the bunch centre (seed 002 Sect. 3.2,
// Eqs. 10-12): slice the cloud with the planes through the PCA box centre normal to
// each PCA axis, take the outline of each slice, close it with Hobby's cubic Bezier
// spline and integrate its arc length.
#pragma once

#include "algorithms/size/pca_box.h"
#include "algorithms/point_cloud.h"
#include "synth/param_table.h"

#include <array>
#include <string>

namespace grapebench {

struct SectionPerimeterParams {
  // Half thickness of each slice, m, [1e-4, 0.05]. Seed 002 measures the truth "within
  // 3 mm of the centroid" with a soft ruler, so the slice keeps points within 3 mm.
  double half_width = 0.003;
  // Outline of a slice: convex_hull (what a tape around the bunch follows; the
  // default, because the truth is a tape measure) or angular (the farthest point in
  // each of angular_bins sectors around the centre: seed 002's "four quadrants"
  // reading, which follows concavities).
  enum class Outline { ConvexHull, Angular };
  Outline outline = Outline::ConvexHull;
  int angular_bins = 72;  // [8, 3600]
  double tension = 1.0;   // Hobby tension, [0.75, 4]
};
const ParamTable<SectionPerimeterParams>& section_perimeter_param_table();

struct SectionPerimeters {
  PcaBox box;
  // m: sections normal to the height (major), length (middle) and width (minor) axis.
  Vec3 perimeter = Vec3::Zero();
  std::array<int, 3> slice_points{};  // points in each slice
  std::array<int, 3> knots{};         // outline points the spline passes through
};

// Throws InputError for a cloud pca_box rejects, bad parameters, or a slice with fewer
// than 3 outline points (naming the section).
SectionPerimeters section_perimeters(const PointCloud& cloud, const SectionPerimeterParams& params = {});

}  // namespace grapebench
