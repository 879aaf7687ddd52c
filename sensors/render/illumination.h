// The light of an outdoor scene, shared by the colour renderers: a sun of finite
// angular size and a sky, both relative (1 = the full sun's irradiance on a surface
// facing it), linear RGB.
#pragma once

#include <Eigen/Core>

#include "synth/types.h"

namespace grapebench {

struct Illumination {
  Vec3 sun_direction = Vec3::UnitZ();  // unit, world, from the scene towards the sun
  double sun = 1.0;                    // the sun's irradiance on a surface facing it (relative)
  double sun_size_deg = 0.53;          // angular diameter of the disc
  Rgb sun_colour{1.0f, 0.96f, 0.90f};  // relative spectrum of direct sunlight (assumed: a warm white)
  enum class Sky { Clear, Overcast };
  Sky sky = Sky::Clear;
  double sky_irradiance = 0.2;  // the sky's irradiance on an unshaded horizontal surface (relative)
};

// Sky radiance by direction (upper hemisphere; the horizon's below it), scaled so that
// the unobstructed sky gives `sky_irradiance` on a horizontal surface. Clear: a blue
// zenith fading to a pale horizon, L = scale (horizon (1 - sqrt z) + zenith sqrt z);
// overcast: the CIE standard overcast sky, L = scale (1 + 2 z) / 3, z the direction's
// sine of elevation.
struct SkyModel {
  Illumination::Sky kind;
  double scale = 0;
  Eigen::Array3d irradiance = Eigen::Array3d::Zero();  // per channel on a horizontal surface (its luminance: sky_irradiance)
  Eigen::Array3d zenith{0.30, 0.50, 1.00}, horizon{0.80, 0.86, 0.96};  // clear sky colours (assumed)
  explicit SkyModel(const Illumination& light);
  Eigen::Array3d shape(double z) const;
  Eigen::Array3d radiance(const Vec3& d) const { return scale * shape(d.z()); }
};

}  // namespace grapebench
