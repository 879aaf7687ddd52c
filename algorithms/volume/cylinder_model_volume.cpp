#include "algorithms/volume/cylinder_model_volume.h"

#include <cmath>

namespace grapebench {

VolumeEstimate cylinder_model_volume(const PointCloud& cloud) {
  require_solid(cloud, "cylinder_model_volume");
  const PcaBox box = pca_box(cloud);
  if (std::max(box.length, box.width) <= 0 || box.height <= 0) {
    throw InputError("cylinder_model_volume: the cloud is flat or a line (a zero PCA extent)");
  }
  const double r = 0.5 * std::max(box.length, box.width);
  VolumeEstimate v;
  v.volume = M_PI * r * r * box.height;  // seed 000, Eq. 6
  v.points_used = static_cast<std::size_t>(cloud.rows());
  v.notes = "2r = max(l, w) = " + std::to_string(2 * r) + " m, h = " + std::to_string(box.height) + " m";
  return v;
}

}  // namespace grapebench
