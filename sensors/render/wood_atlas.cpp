#include "sensors/render/wood_atlas.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <string>

namespace grapebench {

WoodAtlas wood_atlas(const std::vector<Stem>& cylinders, const std::vector<double>& texel, const AppearanceParams& a) {
  if (texel.size() != cylinders.size()) throw std::invalid_argument("wood_atlas: one texel size per cylinder");
  WoodAtlas out;
  out.placement.resize(cylinders.size());
  std::vector<int> w(cylinders.size()), h(cylinders.size());
  for (std::size_t i = 0; i < cylinders.size(); ++i) {
    const Stem& c = cylinders[i];
    const double length = (c.end - c.start).norm();
    if (!(length > 0) || !(c.radius > 0) || !(texel[i] > 0) || !std::isfinite(length / texel[i]))
      throw std::invalid_argument("wood_atlas: cylinder " + std::to_string(i) + " has no length, radius or texel");
    // cycles_scene.py takes images up to 65536 texels a side.
    if (length / texel[i] >= 65535 || 2 * M_PI * c.radius / texel[i] >= 65535)
      throw std::invalid_argument("wood_atlas: cylinder " + std::to_string(i) + " needs more than 65535 texels a side; "
                                  "use a larger texel");
    WoodAtlasPlacement& p = out.placement[i];
    p.along = std::max(1, static_cast<int>(std::ceil(length / texel[i])));
    p.around = std::max(3, static_cast<int>(std::ceil(2 * M_PI * c.radius / texel[i])));
    // The world axis least aligned with the cylinder's, made normal to it.
    const Vec3 axis = (c.end - c.start) / length;
    Vec3 ref = Vec3::Zero();
    int k = 0;
    axis.cwiseAbs().minCoeff(&k);
    ref(k) = 1;
    p.x_axis = (ref - ref.dot(axis) * axis).normalized();
    w[i] = p.along + 1;
    h[i] = p.around + 1;
  }
  // Shelves, tallest rectangle first (ties by index, so the layout is fixed).
  std::vector<std::size_t> order(cylinders.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(), [&](std::size_t x, std::size_t y) { return h[x] > h[y]; });
  out.width = std::max(4096, w.empty() ? 0 : *std::max_element(w.begin(), w.end()));
  std::int64_t x = 0, y = 0, shelf = 0;
  for (std::size_t i : order) {
    if (x + w[i] > out.width) {
      y += shelf;
      x = 0;
      shelf = 0;
    }
    if (y + h[i] > (1 << 28) / out.width)
      throw std::invalid_argument("wood_atlas: more than 2^28 texels; use a larger texel");
    out.placement[i].x0 = static_cast<int>(x);
    out.placement[i].y0 = static_cast<int>(y);
    x += w[i];
    shelf = std::max<std::int64_t>(shelf, h[i]);
  }
  out.height = static_cast<int>(std::max<std::int64_t>(1, y + shelf));
  if (static_cast<double>(out.width) * out.height > static_cast<double>(1 << 28))
    throw std::invalid_argument("wood_atlas: " + std::to_string(out.width) + " x " + std::to_string(out.height) +
                                " texels; use a larger texel");
  out.factor.assign(static_cast<std::size_t>(out.width) * static_cast<std::size_t>(out.height), 32768);
  const double amp = std::max(a.wood_texture, 1e-9);
  for (std::size_t i = 0; i < cylinders.size(); ++i) {
    const Stem& c = cylinders[i];
    const WoodAtlasPlacement& p = out.placement[i];
    const Vec3 axis = (c.end - c.start).normalized(), y_axis = axis.cross(p.x_axis);
    for (int j = 0; j <= p.around; ++j) {
      const double angle = -M_PI + 2 * M_PI * j / p.around;
      const Vec3 radial = c.radius * (std::cos(angle) * p.x_axis + std::sin(angle) * y_axis);
      std::uint16_t* row = &out.factor[static_cast<std::size_t>(p.y0 + j) * static_cast<std::size_t>(out.width) +
                                       static_cast<std::size_t>(p.x0)];
      for (int s = 0; s <= p.along; ++s) {
        const Vec3 point = c.start + (static_cast<double>(s) / p.along) * (c.end - c.start) + radial;
        const double f = (wood_texture_factor(a, point) - 1 + amp) / (2 * amp);
        row[s] = static_cast<std::uint16_t>(std::lround(std::clamp(f, 0.0, 1.0) * 65535));
      }
    }
  }
  return out;
}

}  // namespace grapebench
