#include "bench/instance_mask.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "synth/config.h"

namespace grapebench {

Rle instance_mask(const ImageDetection& a, int width, int height, const std::string& where) {
  if (!a.mask.empty() &&
      (a.mask_x < 0 || a.mask_y < 0 || a.mask_w <= 0 || a.mask_h <= 0 || a.mask_w > width - a.mask_x ||
       a.mask_h > height - a.mask_y || a.mask.size() != static_cast<std::size_t>(a.mask_w) * a.mask_h))
    throw InputError(where + ": mask must lie in the " + std::to_string(width) + " x " + std::to_string(height) +
                     " image and hold mask_w x mask_h values");
  if (!a.rle.empty()) {
    try {
      return rle_from_string(a.rle, height, width);
    } catch (const std::exception& e) {
      throw InputError(where + ": segmentation: " + e.what());
    }
  }
  if (!a.mask.empty()) return rle_encode(a.mask.data(), a.mask_x, a.mask_y, a.mask_w, a.mask_h, width, height);
  // The pixels whose centre lies inside the box. Clamped as doubles first: a hostile
  // box of 1e20 px must not overflow the cast.
  auto edge = [](double x, int hi) { return static_cast<int>(std::clamp(std::ceil(x - 0.5), 0.0, static_cast<double>(hi))); };
  const int u0 = edge(a.x, width), v0 = edge(a.y, height), u1 = edge(a.x + a.w, width), v1 = edge(a.y + a.h, height);
  if (u1 > u0 && v1 > v0) {
    const std::vector<std::uint8_t> ones(static_cast<std::size_t>(u1 - u0) * (v1 - v0), 1);
    return rle_encode(ones.data(), u0, v0, u1 - u0, v1 - v0, width, height);
  }
  const std::uint8_t zero = 0;
  return rle_encode(&zero, 0, 0, 1, 1, width, height);
}

}  // namespace grapebench
