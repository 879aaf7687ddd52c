#include "algorithms/volume/ellipsoid_volume.h"

#include "algorithms/size/ellipsoid_fit.h"

#include <cmath>
#include <cstdio>

namespace grapebench {

VolumeEstimate ellipsoid_volume(const PointCloud& cloud) {
  const EllipsoidFit f = ellipsoid_fit(cloud);
  VolumeEstimate v;
  v.volume = 4.0 / 3.0 * M_PI * f.radii.prod();
  v.watertight = true;  // an ellipsoid is closed
  char notes[96];
  std::snprintf(notes, sizeof notes, "radii %.1f/%.1f/%.1f mm", f.radii[0] * 1e3, f.radii[1] * 1e3, f.radii[2] * 1e3);
  v.notes = notes;
  return v;
}

}  // namespace grapebench
