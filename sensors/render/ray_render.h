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
#include <optional>
#include <span>
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

// What the rays are cast into: the exact scene with the row copies
// (sensors/render/row_copies.h) merged after its foliage, so every ray is cast once.
// Built once and shared by the images of a pair (about 20 ms with a vine row's
// foliage, `BM_RayRenderSceneFoliage`). Refers to `scene`, which must outlive it.
struct RayRenderScene {
  const RayScene* scene = nullptr;  // the exact scene: its foliage is the copies' source
  std::optional<RayScene> merged;   // with the row copies; empty when there are none
  const RayScene& rays() const { return merged ? *merged : *scene; }
};
RayRenderScene ray_render_scene(const RayScene& scene, const AppearanceParams& look);

// The image of `cam` (its pose and intrinsics) of `scene` (built with the same
// `look`); `focal_length` (m) sizes the lens aperture at the camera's f-number.
RayRenderResult ray_render(const RayRenderScene& scene, const Camera& cam, const Illumination& light,
                           const AppearanceParams& look, const PhotoCameraParams& camera, double focal_length,
                           std::uint64_t seed);
// The same view under several lights at once, one image each, in their order: each
// image the same to the bit as ray_render with its light alone (the draws do not
// depend on the light). What does not depend on the light is done once: the camera
// rays and their materials, the sky and mirror rays and what they meet, the edges, the
// sky filter's and the defocus' weights; per light only the sun's shadow rays (from the
// surface and from what the sky rays met) and the sums. `rays` of each result counts
// every ray cast for them all.
std::vector<RayRenderResult> ray_render(const RayRenderScene& scene, const Camera& cam,
                                        std::span<const Illumination> lights, const AppearanceParams& look,
                                        const PhotoCameraParams& camera, double focal_length, std::uint64_t seed);
// The same for one image: the render scene built for it.
RayRenderResult ray_render(const RayScene& scene, const Camera& cam, const Illumination& light,
                           const AppearanceParams& look, const PhotoCameraParams& camera, double focal_length,
                           std::uint64_t seed);

}  // namespace grapebench
