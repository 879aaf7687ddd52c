#include "sensors/sensor.h"


#include <tbb/parallel_for.h>

#include <cmath>

namespace grapebench {

BunchPixels bunch_pixels(const RayScene& scene, const Camera& cam) {
  BunchPixels b;
  b.visible = scene.has_bunch() && cam.ball_pixels(scene.bounds_centre(), scene.bounds_radius(), b.u0, b.v0, b.u1, b.v1);
  return b;
}

OrganisedCloud frame_for(const RayScene& scene, const Camera& cam, const BunchPixels& bp) {
  OrganisedCloud out;
  const int H = cam.K.height;
  if (scene.background()) {
    out.resize(cam.K.width, H);
  } else {
    out.resize(cam.K.width, H, bp.v0, bp.visible ? bp.v1 : bp.v0);
  }
  return out;
}

std::size_t trace_row(const RayScene& scene, const Camera& cam, int v, int ua, int ub, int bu0, int bu1,
                      bool sees_bunch, std::vector<double>& uv, std::vector<Hit>& hits) {
  hits.resize(cam.K.width);
  const PixelRays ray_at = cam.pixel_rays();
  for (int u = ua; u < ub; ++u) {
    if (!(sees_bunch && u >= bu0 && u < bu1)) hits[u] = scene.background_hit(ray_at(u + 0.5, v + 0.5));
  }
  if (!sees_bunch) return 0;
  uv.resize(2 * static_cast<std::size_t>(bu1 - bu0));
  for (int u = bu0; u < bu1; ++u) {
    uv[2 * (u - bu0)] = u + 0.5;
    uv[2 * (u - bu0) + 1] = v + 0.5;
  }
  scene.intersect_image_points(ray_at, uv.data(), bu1 - bu0, hits.data() + bu0);
  return static_cast<std::size_t>(bu1 - bu0);
}

void for_rows(int height, const std::function<void(int, int)>& body) {
  const int block = 8;
  tbb::parallel_for(0, (height + block - 1) / block, [&](int b) {
    body(b * block, std::min(height, (b + 1) * block));
  });
}

}  // namespace grapebench
