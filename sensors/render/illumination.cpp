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
  Eigen::Array3d e = Eigen::Array3d::Zero();
  const int n = 256;
  for (int i = 0; i < n; ++i) {
    const double z = (i + 0.5) / n;
    e += shape(z) * z / n;
  }
  e *= 2 * M_PI;
  scale = light.sky_irradiance / (0.2126 * e[0] + 0.7152 * e[1] + 0.0722 * e[2]);
  irradiance = scale * e;
}

}  // namespace grapebench
