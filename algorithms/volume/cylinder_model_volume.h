// GM: geometric (cylinder) model of seed 000.
#pragma once

#include "algorithms/size/pca_box.h"
#include "algorithms/volume_estimate.h"

namespace grapebench {

// Seed 000, Eq. 6: V = pi r^2 h with 2r = max(l, w) and h the height, all from the
// PCA box (Eq. 5). No parameters. Throws InputError on degenerate clouds.
VolumeEstimate cylinder_model_volume(const PointCloud& cloud);

}  // namespace grapebench
