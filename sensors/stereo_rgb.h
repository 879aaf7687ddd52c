// Binocular colour stereo rig of seed 001: two rectified 800 x 600 colour cameras,
// 6 mm lenses, 5 cm baseline. Left and right images are rendered with OSMesa from
// the bunch's triangle mesh (smooth shading, specular highlights, berry colours,
// plain or foliage background); the organised cloud of the left camera carries the
// exact depth and labels from the ray scene, so estimators that match the images
// can be scored pixel by pixel.
#pragma once

#include "sensors/sensor.h"

namespace grapebench {

struct StereoRgbParams {
  int width = 800, height = 600;  // pixels (seed 001: 600 x 800), [64, 4096]
  double focal_length_mm = 6.0;   // seed 001: 6 mm lens, [1, 100]
  double pixel_pitch_um = 6.0;    // assumed (not stated in seed 001): 1000 px focal length, [1, 50]
  double baseline = 0.05;         // m, seed 001: 5 cm, [0.01, 1]
  enum class Background { Foliage, Plain };
  Background background = Background::Foliage;  // foliage texture or a plain colour
  Rgb plain_colour{0.55f, 0.6f, 0.65f};
  double background_distance = 0.4;  // m behind the bunch, [0.05, 10]
  double specular = 0.5;             // specular strength, [0, 1]
  double shininess = 40;             // Phong exponent, [1, 128]
  int mesh_level = 3;                // icosphere level of the rendered berries, [1, 5]
  double noise_scale = 1.0;          // image noise sd = 2/255 * noise_scale, [0, 20]
  // Light (seed 001 Sect. 3.1's three conditions as presets). lamp: a lamp beside the
  // camera, no shadows (the default; images as before). The others are a directional
  // sun with shadows cast in the exact ray scene (bunch and foliage) plus an ambient
  // term; each preset sets the sun's elevation and azimuth (0: behind the camera,
  // 180: behind the cluster, facing the camera), its strength, the ambient and how
  // bright the backdrop is. custom: those five keys from the scene.
  enum class Light { Lamp, Front, Overshadow, Overcast, Custom };
  Light light = Light::Lamp;
  double sun_elevation_deg = 45, sun_azimuth_deg = 25;  // custom only
  double sun = 0.8, ambient = 0.25, backdrop = 1.0;     // custom only: relative intensities
  double exposure = 1.0;                                // gain on every pixel before the noise, [0.1, 10]
  // Leaf texture: each leaf triangle split into texture_cells^2 and every vertex's
  // colour varied by this relative amplitude, fixed to the leaf surface (hashed from the
  // world position), so matching and SIFT find features on leaves as on real ones
  // (veins, blotches). 0: flat leaves (seed 001's scenes, unchanged).
  double leaf_texture = 0;  // [0, 1]
  int texture_cells = 8;    // [1, 32]
};
// The sun of a light preset (custom: the params' own).
struct SunLight {
  double elevation_deg, azimuth_deg, sun, ambient, backdrop;
};
SunLight sun_light(const StereoRgbParams& p);
// The scene keys of `sensor: {type: ...}` for this model.
const ParamTable<StereoRgbParams>& stereo_rgb_param_table();

class StereoRgb : public Sensor {
 public:
  explicit StereoRgb(const StereoRgbParams& p) : p_(p) {}
  std::string type() const override { return "stereo_rgb"; }
  Intrinsics intrinsics() const override;
  OrganisedCloud capture(const RayScene& scene, const Eigen::Isometry3d& pose, std::uint64_t seed) const override;
  nlohmann::ordered_json describe() const override;

 private:
  StereoRgbParams p_;
};

}  // namespace grapebench
