#include "sensors/render/appearance.h"

#include <array>
#include <cmath>

#include "synth/rng.h"

namespace grapebench {

double value_noise(const Vec3& p, double cell, std::uint64_t salt) {
  // Trilinear interpolation of hashed lattice values (a smoothstep per axis).
  const Vec3 q = p / cell;
  const Vec3 f0(std::floor(q.x()), std::floor(q.y()), std::floor(q.z()));
  const Vec3 f = q - f0;
  const auto lattice = [&](int dx, int dy, int dz) {
    const auto c = [](double v, int d) { return static_cast<std::uint64_t>(static_cast<std::int64_t>(v) + d + (1 << 24)); };
    const std::uint64_t key = (c(f0.x(), dx) * 73856093ULL) ^ (c(f0.y(), dy) * 19349663ULL) ^ (c(f0.z(), dz) * 83492791ULL);
    return 2 * hashed_uniform(salt, key) - 1;
  };
  const auto s = [](double t) { return t * t * (3 - 2 * t); };
  const double sx = s(f.x()), sy = s(f.y()), sz = s(f.z());
  double v = 0;
  for (int dz = 0; dz < 2; ++dz)
    for (int dy = 0; dy < 2; ++dy)
      for (int dx = 0; dx < 2; ++dx)
        v += (dx ? sx : 1 - sx) * (dy ? sy : 1 - sy) * (dz ? sz : 1 - sz) * lattice(dx, dy, dz);
  return v;
}

namespace {
Rgb scaled(const Rgb& c, double k) {
  const auto f = [k](float v) { return static_cast<float>(std::clamp(v * k, 0.0, 1.0)); };
  return {f(c.r), f(c.g), f(c.b)};
}
}  // namespace

Material berry_material(const AppearanceParams& a, const Rgb& base) {
  // The bloom as a thin diffuse layer over the skin: its own reflectance where it
  // covers, the skin seen through it otherwise (the layer's absorption neglected).
  const double c = a.bloom;
  const auto mix = [c](float skin, float bloom) { return static_cast<float>((1 - c) * skin + c * std::min(1.0, bloom + skin * (1.0 - bloom))); };
  Material m;
  // Translucency takes its share from the diffuse reflectance (reflected plus
  // transmitted stays the skin's albedo: no energy made).
  const Rgb t = scaled(base, a.translucency);
  m.albedo = {std::max(0.0f, mix(base.r, a.bloom_reflectance.r) - t.r), std::max(0.0f, mix(base.g, a.bloom_reflectance.g) - t.g),
              std::max(0.0f, mix(base.b, a.bloom_reflectance.b) - t.b)};
  m.transmittance = t;
  // Bloom scatters the cuticle's mirror lobe: weaker and rougher where it covers
  // (wax removal raises gloss: Ward and Nussinovitch 1996).
  m.specular = a.skin_f0 * (1 - 0.5 * c);
  m.roughness = (1 - c) * a.skin_roughness + c * a.bloom_roughness;
  return m;
}

Material leaf_material(const AppearanceParams& a, const Vec3& point, const Vec3& centre, const Vec3& tip,
                       const Vec3& normal, double shade, bool upper) {
  // Distance to the nearest main vein: the five lines from the petiole (leaf centre)
  // to the lobe tips, every 72 deg in the leaf's plane. The nearest is the one whose
  // direction has the largest dot product with the point (no atan2, sin, cos: they
  // were a tenth of a foliage image's shading).
  static const std::array<double, 5> vc{1, std::cos(0.4 * M_PI), std::cos(0.8 * M_PI), std::cos(1.2 * M_PI), std::cos(1.6 * M_PI)};
  static const std::array<double, 5> vs{0, std::sin(0.4 * M_PI), std::sin(0.8 * M_PI), std::sin(1.2 * M_PI), std::sin(1.6 * M_PI)};
  const Vec3 e1 = (tip - centre).normalized();
  const Vec3 e2 = normal.cross(e1).normalized();
  const Vec3 d = point - centre;
  const double x = d.dot(e1), y = d.dot(e2);
  const double r = std::sqrt(x * x + y * y);
  std::size_t nearest = 0;
  double best = x;
  for (std::size_t j = 1; j < 5; ++j) {
    const double c = x * vc[j] + y * vs[j];
    if (c > best) best = c, nearest = j;
  }
  const double radius = (tip - centre).norm();
  const double along = std::clamp(r / std::max(radius, 1e-6), 0.0, 1.0);
  const double width = a.vein_width * (1 - 0.7 * along);  // veins taper to the tips
  const double dist = std::abs(x * vs[nearest] - y * vc[nearest]);
  const double q = width > 0 ? dist / (0.5 * width) : 0;
  const double vein = width > 0 && best > 0 ? std::exp(-0.5 * q * q) : 0;
  const double texture = 1 + a.leaf_texture * (0.7 * value_noise(point, 0.004, 0x1eaf) + 0.3 * value_noise(point, 0.0012, 0x1eb0));
  const double k = shade * texture * (1 + a.vein_contrast * vein) * (upper ? 1.0 : a.leaf_back);
  Material m;
  m.albedo = scaled(a.leaf_reflectance, k);
  m.transmittance = scaled(a.leaf_transmittance, shade * texture);
  m.specular = upper ? 0.03 : 0.0;  // the upper cuticle's faint sheen (leaf wax, n about 1.4)
  m.roughness = 0.35;
  return m;
}

double wood_texture_factor(const AppearanceParams& a, const Vec3& point) {
  return 1 + a.wood_texture * value_noise(point, 0.002, 0x57e3);
}

Material wood_material(const AppearanceParams& a, const Vec3& point, const Rgb& colour) {
  Material m;
  m.albedo = scaled(colour, wood_texture_factor(a, point));
  m.transmittance = {0, 0, 0};
  m.specular = 0;
  m.roughness = 1;
  return m;
}

const ParamTable<AppearanceParams>& appearance_param_table() {
  using P = AppearanceParams;
  static const ParamTable<P> table =
      ParamTable<P>()
          .real("skin_f0", "-", &P::skin_f0, 0, 0.2,
                "berry cuticle's Fresnel reflectance at normal incidence: ((n-1)/(n+1))^2, n = 1.46 (plant wax)")
          .real("skin_roughness", "-", &P::skin_roughness, 0.01, 1, "GGX alpha of bare, polished skin (assumed: a sharp highlight)")
          .real("bloom", "-", &P::bloom, 0, 1,
                "wax bloom cover: a matte blue-grey haze on dark berries; 0 polished (assumed 0.6 for field fruit)")
          .rgb("bloom_reflectance", &P::bloom_reflectance,
               "the bloom layer's diffuse reflectance (assumed: blue-grey, a bloomed black grape reads about 0.07)")
          .real("bloom_roughness", "-", &P::bloom_roughness, 0.01, 1,
                "GGX alpha under bloom (wax removal raises gloss: Ward and Nussinovitch 1996)")
          .real("translucency", "-", &P::translucency, 0, 1,
                "share of a berry's albedo transmitted, not reflected (green and white berries glow backlit; assumed)")
          .rgb("leaf_reflectance", &P::leaf_reflectance,
               "upper leaf face at 650 / 550 / 450 nm: Cabernet Sauvignon, Helios' leaf library")
          .rgb("leaf_transmittance", &P::leaf_transmittance, "the same leaf's transmittance at 650 / 550 / 450 nm")
          .real("leaf_back", "-", &P::leaf_back, 0.5, 3, "lower (abaxial, hairy) face over the upper's reflectance (assumed)")
          .real("leaf_texture", "-", &P::leaf_texture, 0, 1, "within-leaf variation, 4 and 1.2 mm value noise")
          .real("vein_width", "m", &P::vein_width, 0, 0.005, "main veins' width at the petiole, tapering to the lobe tips")
          .real("vein_contrast", "-", &P::vein_contrast, 0, 3, "reflectance gain on a vein (veins are paler)")
          .real("wood_texture", "-", &P::wood_texture, 0, 1, "variation of stems, canes and cordon (2 mm value noise)")
          .rgb("ground_reflectance", &P::ground_reflectance, "bare soil (dry loam 0.15-0.25: Oke, Boundary Layer Climates)")
          .real("ground_below", "m", &P::ground_below, 0.05, 10, "ground below the bunch's lowest point (VSP fruit zone about 1 m)")
          .real("row_spacing", "m", &P::row_spacing, 0, 10, "between vine rows; 0: no rows behind")
          .real("vine_spacing", "m", &P::vine_spacing, 0, 10, "the foliage repeated along the row at this pitch; 0: once")
          .integer("rows_behind", "count", &P::rows_behind, 0, 4, "vine rows drawn behind the bunch's own")
          .integer("post_every", "count", &P::post_every, 0, 20,
                   "a trellis post every this many vines in the row copies, between two vines, ground to the canopy's "
                   "top (line posts every 5-8 m, common practice; assumed); never beside the scene's own vine; 0 none")
          .real("post_radius", "m", &P::post_radius, 0.01, 0.2, "post radius (steel line posts about 8 cm across)");
  return table;
}

}  // namespace grapebench
