#include "sensors/render/illumination.h"

#include <algorithm>
#include <cmath>

namespace grapebench {

Eigen::Array3d SkyModel::shape(double z) const {
  z = std::clamp(z, 0.0, 1.0);
  if (kind == Illumination::Sky::Overcast) return Eigen::Array3d::Constant((1 + 2 * z) / 3);
  const double t = std::sqrt(z);
  return horizon * (1 - t) + zenith * t;
}

SkyModel::SkyModel(const Illumination& light) : kind(light.sky) {
  // Irradiance of the unscaled sky on a horizontal surface: 2 pi Int L(z) z dz, in
  // luminance (Rec. 709 weights), by the midpoint rule.
  double e = 0;
  const int n = 256;
  for (int i = 0; i < n; ++i) {
    const double z = (i + 0.5) / n;
    const Eigen::Array3d c = shape(z);
    e += (0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]) * z / n;
  }
  scale = light.sky_irradiance / (2 * M_PI * e);
}

}  // namespace grapebench
