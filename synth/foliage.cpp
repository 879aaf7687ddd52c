#include "synth/foliage.h"

#include "synth/rng.h"

#include <algorithm>
#include <cmath>

namespace grapebench {

const ParamTable<FoliageParams>& foliage_param_table() {
  using F = FoliageParams;
  static const ParamTable<F> table = ParamTable<F>()
      .integer("leaves", "count", &F::leaves, 0, 2000, "leaves drawn in the canopy box around the bunch")
      .real("leaf_radius", "m", &F::leaf_radius, 0.01, 0.3, "mean lobe tip radius of a five-lobed leaf")
      .real("leaf_radius_sd", "m", &F::leaf_radius_sd, 0, 0.1, "sd of the leaf radius")
      .real("row_half_length", "m", &F::row_half_length, 0.05, 5, "leaves and cordon span x in centre +- this")
      .real("canopy_depth", "m", &F::canopy_depth, 0, 2, "leaves' y range, across the row")
      .real("canopy_below", "m", &F::canopy_below, 0, 2, "leaves reach this far below the bunch bottom")
      .real("canopy_above", "m", &F::canopy_above, 0, 2, "leaves reach this far above the cordon")
      .real("clearance", "m", &F::clearance, 0, 0.5, "gap leaves keep to the bunch's berries")
      .real("occlusion", "-", &F::occlusion, 0, 1,
            "chance a leaf between the row's front and the bunch, over its silhouette, is kept (0: face clear)")
      .real("cordon_radius", "m", &F::cordon_radius, 0.002, 0.05, "radius of the horizontal cane carrying the bunch")
      .integer("shoots", "count", &F::shoots, 0, 100, "vertical canes rising from the cordon")
      .real("shoot_radius", "m", &F::shoot_radius, 0.002, 0.05, "shoot radius")
      .rgb("leaf_colour", &F::leaf_colour, "mean leaf colour, linear RGB, varied per leaf")
      .real("leaf_colour_sd", "-", &F::leaf_colour_sd, 0, 1, "relative sd of the per-leaf colour")
      .rgb("cane_colour", &F::cane_colour, "colour of cordon and shoots")
      .integer("wire_pairs", "count", &F::wire_pairs, 0, 4,
               "foliage wire pairs above the cordon, one wire on each face of the canopy (VSP trellises carry 2-3: "
               "Smart and Robinson 1991, Sunlight into Wine); 0 none")
      .real("wire_spacing", "m", &F::wire_spacing, 0.05, 1,
            "height of the first pair above the cordon and between pairs (VSP: about 0.3 m, Smart and Robinson 1991)")
      .real("wire_radius", "m", &F::wire_radius, 0.0005, 0.005, "trellis wire radius (2.5 mm high-tensile wire)")
      .rgb("trellis_colour", &F::trellis_colour,
           "wires and posts, linear RGB (weathered galvanised steel, a mid grey; assumed)");
  return table;
}

FoliageParams read_foliage(const ConfigNode& n) {
  FoliageParams p;
  foliage_param_table().read(n, p);
  return p;
}

namespace {

// Distance from segment [a, b] to point x.
double segment_distance(const Vec3& a, const Vec3& b, const Vec3& x) {
  const Vec3 ab = b - a;
  const double t = std::clamp((x - a).dot(ab) / std::max(ab.squaredNorm(), 1e-300), 0.0, 1.0);
  return (a + t * ab - x).norm();
}

// Whether a disc (centre c, unit normal n, radius r) comes within `gap` of a sphere.
bool disc_touches_sphere(const Vec3& c, const Vec3& n, double r, const Vec3& centre, double radius, double gap) {
  const Vec3 d = centre - c;
  const double h = d.dot(n);             // sphere centre's height above the disc's plane
  const double rho = (d - h * n).norm();  // and its distance from the disc's axis
  const double q = std::max(0.0, rho - r);
  return std::hypot(q, h) < radius + gap;
}

}  // namespace

Foliage generate_foliage(const FoliageParams& p, const Bunch& bunch, std::uint64_t seed) {
  Foliage f;
  f.cane_colour = p.cane_colour;
  f.trellis_colour = p.trellis_colour;
  Rng rng(derive_seed(seed, 0xf011a6e));
  // The bunch's extent, for the canopy box and the clearance test.
  Vec3 lo = Vec3::Constant(1e300), hi = Vec3::Constant(-1e300);
  for (const auto& b : bunch.berries) {
    lo = lo.cwiseMin(b.centre - Vec3::Constant(b.radius));
    hi = hi.cwiseMax(b.centre + Vec3::Constant(b.radius));
  }
  if (bunch.berries.empty()) lo = hi = bunch.top;
  const Vec3 anchor = bunch.peduncle >= 0 ? bunch.stems[static_cast<std::size_t>(bunch.peduncle)].end : bunch.top;
  const double cx = 0.5 * (lo.x() + hi.x()), cy = 0.5 * (lo.y() + hi.y());

  // The cordon: a horizontal cane along x through the peduncle's end.
  Stem cordon;
  cordon.start = anchor - Vec3(p.row_half_length, 0, 0);
  cordon.end = anchor + Vec3(p.row_half_length, 0, 0);
  cordon.radius = p.cordon_radius;
  cordon.part = Part::Cane;
  f.canes.push_back(cordon);
  for (int k = 0; k < p.shoots; ++k) {
    Stem s;
    const double x = anchor.x() + rng.uniform(-p.row_half_length, p.row_half_length);
    s.start = Vec3(x, anchor.y(), anchor.z());
    // Draws one per statement: the order of a call's arguments is unspecified (GCC
    // took them last first, clang first first); this is the order GCC gave.
    const double lean_y = rng.normal(0, 0.15), lean_x = rng.normal(0, 0.25);
    const Vec3 lean(lean_x, lean_y, 1);
    s.end = s.start + (p.canopy_above / lean.z()) * lean;
    s.radius = p.shoot_radius;
    s.part = Part::Cane;
    f.canes.push_back(s);
  }

  // Leaves: five-lobed outlines r(phi) = R (0.72 + 0.28 cos 5 phi), facing the row's
  // sides (normal mostly along +-y) with a random tilt; rejected where they would come
  // closer than `clearance` to a berry or cut a cane. 24 outline points per leaf.
  const int kOutline = 24;
  const double z_lo = lo.z() - p.canopy_below, z_hi = anchor.z() + p.canopy_above;
  int placed = 0;
  for (int attempt = 0; placed < p.leaves && attempt < 50 * std::max(p.leaves, 1); ++attempt) {
    const double r = std::max(0.01, rng.normal(p.leaf_radius, p.leaf_radius_sd));
    const double cz = rng.uniform(z_lo, z_hi), cy_draw = rng.uniform(-0.5, 0.5),
                 cx_draw = rng.uniform(-p.row_half_length, p.row_half_length);  // in GCC's order, as above
    const Vec3 c(cx + cx_draw, cy + cy_draw * p.canopy_depth, cz);
    const double nz = rng.normal(0, 0.5), ny = rng.uniform() < 0.5 ? -1.0 : 1.0, nx = rng.normal(0, 0.5);
    Vec3 n = Vec3(nx, ny, nz).normalized();
    const bool in_front = c.y() < cy && c.x() + r > lo.x() && c.x() - r < hi.x() && c.z() + r > lo.z() && c.z() - r < hi.z();
    const double keep = rng.uniform();
    if (in_front && keep >= p.occlusion) continue;
    bool clash = false;
    for (const auto& b : bunch.berries) {
      if (disc_touches_sphere(c, n, r, b.centre, b.radius, p.clearance)) {
        clash = true;
        break;
      }
    }
    for (const auto& s : bunch.stems) clash = clash || segment_distance(s.start, s.end, c) < r + s.radius + p.clearance;
    for (const auto& s : f.canes) clash = clash || segment_distance(s.start, s.end, c) < s.radius + 0.2 * r;
    if (clash) continue;
    // An orthonormal frame in the leaf's plane, spun at random.
    const Vec3 e1 = n.unitOrthogonal();
    const Vec3 e2 = n.cross(e1);
    const double spin = rng.uniform(0, 2 * M_PI);
    const int base = static_cast<int>(f.vertices.size());
    f.vertices.push_back(c);
    for (int k = 0; k < kOutline; ++k) {
      const double phi = 2 * M_PI * k / kOutline;
      const double rk = r * (0.72 + 0.28 * std::cos(5 * phi));
      f.vertices.push_back(c + rk * (std::cos(phi + spin) * e1 + std::sin(phi + spin) * e2));
    }
    const double shade = 1 + p.leaf_colour_sd * rng.normal();
    const Rgb col{static_cast<float>(std::clamp(p.leaf_colour.r * shade, 0.0, 1.0)),
                  static_cast<float>(std::clamp(p.leaf_colour.g * shade, 0.0, 1.0)),
                  static_cast<float>(std::clamp(p.leaf_colour.b * shade, 0.0, 1.0))};
    for (int k = 0; k < kOutline; ++k) {
      f.triangles.push_back({base, base + 1 + k, base + 1 + (k + 1) % kOutline});
      f.triangle_colour.push_back(col);
    }
    ++placed;
  }
  // The foliage wires: straight along the row, through whatever leaves they meet (a
  // real canopy is tucked between them).
  for (int k = 1; k <= p.wire_pairs; ++k) {
    for (const double side : {-0.5, 0.5}) {
      Stem w;
      const Vec3 at = anchor + Vec3(0, side * p.canopy_depth, k * p.wire_spacing);
      w.start = at - Vec3(p.row_half_length, 0, 0);
      w.end = at + Vec3(p.row_half_length, 0, 0);
      w.radius = p.wire_radius;
      w.part = Part::Background;
      f.canes.push_back(w);
    }
  }
  return f;
}

}  // namespace grapebench
