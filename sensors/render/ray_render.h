// The fast physically based colour renderer: Embree rays through the exact scene the
// labels come from (spheres, cylinders, leaf triangles; no tessellation) plus the row
// copies, shaded with the appearance model under a sun of finite size and a sky. One
// ray through each pixel's centre, samples^2 more where what is seen changes (edges:
// anti-aliasing); per ray one shadow ray to a point of the sun's disc (soft shadows),
// one sky ray per lit face (sky visibility, the ground, and one bounce off whatever it
// meets, lit without a further visibility test) and, on glossy surfaces, one mirror
// ray. The sky rays' noise is filtered across neighbouring pixels of the same part
// (a joint bilateral filter on depth and normal); defocus is a gather blur by each
// pixel's circle of confusion. Every draw hashed from the seed and the pixel: the
// image is the same at any thread count. Validated against Cycles
// (sensors/render/cycles_render.h; bench/perf/render_agreement.cpp).
#pragma once

#include <cstdint>
#include <vector>

#include "sensors/camera.h"
#include "sensors/ray_scene.h"
#include "sensors/render/appearance.h"
#include "sensors/render/develop_image.h"
#include "sensors/render/illumination.h"

namespace grapebench {

struct RayRenderResult {
  std::vector<float> linear;  // H x W x 3, radiance times pi (1 = white paper in the full sun)
  std::uint64_t rays = 0;     // every ray cast, for the speed table
};

// The image of `cam` (its pose and intrinsics) of `scene`; `focal_length` (m) sizes
// the lens aperture at the camera's f-number.
RayRenderResult ray_render(const RayScene& scene, const Camera& cam, const Illumination& light,
                           const AppearanceParams& look, const PhotoCameraParams& camera, double focal_length,
                           std::uint64_t seed);

}  // namespace grapebench
