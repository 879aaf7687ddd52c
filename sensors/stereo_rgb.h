// Binocular colour stereo rig of seed 001: two rectified 800 x 600 colour cameras,
// 6 mm lenses, 5 cm baseline. Left and right images are rendered with OSMesa from
// the bunch's triangle mesh (smooth shading, specular highlights, berry colours,
// plain or foliage background), or, with `renderer: ray` or `cycles`, photoreal
// (sensors/render/); the organised cloud of the left camera carries the exact depth
// and labels from the ray scene, so estimators that match the images can be scored
// pixel by pixel.
#pragma once

#include "sensors/render/appearance.h"
#include "sensors/render/cycles_render.h"
#include "sensors/render/develop_image.h"
#include "sensors/render/illumination.h"
#include "sensors/sensor.h"

namespace grapebench {

struct StereoRgbParams {
  int width = 800, height = 600;  // pixels (seed 001: 600 x 800), [64, 4096]
  double focal_length_mm = 6.0;   // seed 001: 6 mm lens, [1, 100]
  double pixel_pitch_um = 6.0;    // assumed (not stated in seed 001): 1000 px focal length, [1, 50]
  double baseline = 0.05;         // m, seed 001: 5 cm, [0.01, 1]
  bool right_image = true;        // false: the left image only (datasets)
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
  // Which renderer makes the images: opengl (OSMesa, Phong shading, the images every
  // result so far was measured on); ray (sensors/render/ray_render.h: the appearance
  // model under a sun and sky); cycles (sensors/render/cycles_render.h: the same scene
  // path traced by Blender, the reference). ray and cycles go through the camera chain
  // of sensors/render/develop_image.h.
  enum class Renderer { OpenGl, Ray, Cycles };
  Renderer renderer = Renderer::OpenGl;
  double sun_size_deg = 0.53;  // ray: the sun's angular diameter (soft shadows), [0, 20]
  // ray and cycles: 0 keeps the scene's draws; another value redraws the renderer's
  // sampling and the camera's noise with the scene, its truth and the rig unchanged, so
  // a figure's spread over the images' own noise can be measured, [0, 1000000].
  int noise_seed = 0;
  AppearanceParams appearance;  // ray: section `appearance:`
  PhotoCameraParams camera;     // ray: section `camera:`
  CyclesParams cycles;          // cycles: section `cycles:`
};
// The sun of a light preset (custom: the params' own).
struct SunLight {
  double elevation_deg, azimuth_deg, sun, ambient, backdrop;
};
SunLight sun_light(const StereoRgbParams& p);
// The ray and cycles renderers' light for a camera at `pose`: the preset's sun about
// the vertical from behind the camera, its sky.
Illumination stereo_rgb_illumination(const StereoRgbParams& p, const Eigen::Isometry3d& pose);
// The scene keys of `sensor: {type: ...}` for this model.
const ParamTable<StereoRgbParams>& stereo_rgb_param_table();

class StereoRgb : public Sensor {
 public:
  explicit StereoRgb(const StereoRgbParams& p) : p_(p) {}
  std::string type() const override { return "stereo_rgb"; }
  Intrinsics intrinsics() const override;
  OrganisedCloud capture(const RayScene& scene, const Eigen::Isometry3d& pose, std::uint64_t seed) const override;
  nlohmann::ordered_json describe() const override;
  // renderer ray: every key but the light's (light, the custom sun and sky, the sun's
  // size); the others: none (captured alone).
  std::string together_key() const override;
  // renderer ray: the pair under each sensor's light from one ray_render call per
  // camera (sensors/render/ray_render.h) and one exact label image.
  std::vector<OrganisedCloud> capture_together(std::span<const Sensor* const> sensors, const RayScene& scene,
                                               const Eigen::Isometry3d& pose, std::uint64_t seed) const override;
  // Its parameters: what the dataset writer needs to label the scene its images show.
  const StereoRgbParams& params() const { return p_; }

 private:
  StereoRgbParams p_;
};

}  // namespace grapebench
