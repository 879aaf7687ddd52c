#include "synth/surface_sample.h"

#include "synth/config.h"
#include "synth/rng.h"
#include "synth/stem_geometry.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace grapebench {

namespace {

// One primitive of the solid: a berry (index >= 0) or a stem (-1 - index), with its
// axis-aligned bounds for the neighbour lists.
struct Primitive {
  int id;
  Vec3 lo, hi;
};

bool inside_primitive(const Bunch& b, int id, const Vec3& x) {
  if (id >= 0) {
    const Berry& berry = b.berries[static_cast<std::size_t>(id)];
    return (x - berry.centre).squaredNorm() <= berry.radius * berry.radius;
  }
  return inside_stem(b.stems[static_cast<std::size_t>(-1 - id)], x);
}

Vec3 unit_sphere_point(Rng& rng) {
  // Archimedes: z uniform on [-1, 1] and an angle give the uniform measure on S^2.
  const double z = rng.uniform(-1, 1), phi = rng.uniform(0, 2 * M_PI);
  const double s = std::sqrt(std::max(0.0, 1 - z * z));
  return {s * std::cos(phi), s * std::sin(phi), z};
}

}  // namespace

SurfaceSample sample_surface(const Bunch& b, double density, std::uint64_t seed) {
  if (!(density > 0 && density <= 1e9)) {
    throw InputError("sample_surface: density = " + std::to_string(density) +
                     " points/m2 outside the allowed range (0, 1e9]");
  }
  std::vector<Primitive> prims;
  double area = 0;
  for (std::size_t i = 0; i < b.berries.size(); ++i) {
    const Berry& x = b.berries[i];
    prims.push_back({static_cast<int>(i), x.centre.array() - x.radius, x.centre.array() + x.radius});
    area += 4 * M_PI * x.radius * x.radius;
  }
  for (std::size_t i = 0; i < b.stems.size(); ++i) {
    const Stem& s = b.stems[i];
    prims.push_back({-1 - static_cast<int>(i), s.start.cwiseMin(s.end).array() - s.radius,
                     s.start.cwiseMax(s.end).array() + s.radius});
    area += 2 * M_PI * s.radius * ((s.end - s.start).norm() + s.radius);
  }
  if (density * area > 5e7) {
    throw InputError("sample_surface: density = " + std::to_string(density) + " points/m2 draws " +
                     std::to_string(density * area) + " candidates on this bunch, more than 5e7; lower density");
  }
  // Which primitives can contain a point of primitive k: those whose bounds overlap.
  std::vector<std::vector<int>> neighbours(prims.size());
  for (std::size_t k = 0; k < prims.size(); ++k) {
    for (std::size_t j = 0; j < prims.size(); ++j) {
      if (j == k) continue;
      if ((prims[k].lo.array() <= prims[j].hi.array()).all() && (prims[j].lo.array() <= prims[k].hi.array()).all()) {
        neighbours[k].push_back(prims[j].id);
      }
    }
  }

  SurfaceSample out;
  Rng rng(seed);
  // Draws n points on one surface piece of primitive k and keeps the exposed ones.
  const auto draw = [&](std::size_t k, double piece_area, Part part, const auto& point_and_normal) {
    const auto n = static_cast<std::size_t>(std::llround(density * piece_area));
    out.candidates += n;
    for (std::size_t i = 0; i < n; ++i) {
      Vec3 p, normal;
      point_and_normal(p, normal);
      bool buried = false;
      for (const int j : neighbours[k]) {
        if (inside_primitive(b, j, p)) {
          buried = true;
          break;
        }
      }
      if (buried) continue;
      out.points.push_back(p);
      out.normals.push_back(normal);
      out.parts.push_back(part);
      out.weights.push_back(piece_area / static_cast<double>(n));
    }
  };
  for (std::size_t k = 0; k < prims.size(); ++k) {
    const int id = prims[k].id;
    if (id >= 0) {
      const Berry& x = b.berries[static_cast<std::size_t>(id)];
      draw(k, 4 * M_PI * x.radius * x.radius, Part::Berry, [&](Vec3& p, Vec3& n) {
        n = unit_sphere_point(rng);
        p = x.centre + x.radius * n;
      });
      continue;
    }
    const Stem& s = b.stems[static_cast<std::size_t>(-1 - id)];
    const Vec3 axis = s.end - s.start;
    const double length = axis.norm();
    if (!(length > 0) || !(s.radius > 0)) {
      throw InputError("sample_surface: stem " + std::to_string(-1 - id) + " has zero length or radius");
    }
    const Vec3 w = axis / length;
    Vec3 e1, e2;
    perpendicular_basis(w, e1, e2);
    draw(k, 2 * M_PI * s.radius * length, s.part, [&](Vec3& p, Vec3& n) {
      const double phi = rng.uniform(0, 2 * M_PI), t = rng.uniform(0, length);
      n = std::cos(phi) * e1 + std::sin(phi) * e2;
      p = s.start + t * w + s.radius * n;
    });
    for (const bool at_end : {false, true}) {
      draw(k, M_PI * s.radius * s.radius, s.part, [&](Vec3& p, Vec3& n) {
        // Uniform on the disc: radius sqrt(u) R.
        const double r = s.radius * std::sqrt(rng.uniform()), phi = rng.uniform(0, 2 * M_PI);
        n = at_end ? w : Vec3(-w);
        p = (at_end ? s.end : s.start) + r * (std::cos(phi) * e1 + std::sin(phi) * e2);
      });
    }
  }
  return out;
}

}  // namespace grapebench
