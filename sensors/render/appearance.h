// The appearance model every physically based colour renderer shares: what each part
// of the scene reflects and transmits, and the light that reaches it. Reflectances are
// linear, per channel (R, G, B read at 650, 550, 450 nm), in [0, 1]. Colours the
// generator draws per instance (berry colour per variety and ripeness, per-leaf shade,
// stem and cane colours) stay the synth's; this table adds the surface physics and the
// within-surface variation. Scene section `appearance:` of a colour sensor.
#pragma once

#include "synth/param_table.h"
#include "synth/types.h"

namespace grapebench {

struct AppearanceParams {
  // Berry skin: a glossy dielectric (the cuticle's wax, refractive index about 1.46)
  // under an optional wax bloom, a rough scattering layer that makes dark berries look
  // bluish-grey and matte.
  double skin_f0 = 0.035;         // Fresnel reflectance at normal incidence, ((n-1)/(n+1))^2 for n = 1.46, [0, 0.2]
  double skin_roughness = 0.10;   // GGX alpha of bare (polished) skin, [0.01, 1]
  double bloom = 0.6;             // bloom cover, [0, 1]; 0: polished berries
  Rgb bloom_reflectance{0.060f, 0.066f, 0.085f};  // the bloom layer's own diffuse reflectance
  double bloom_roughness = 0.45;  // GGX alpha where bloom covers, [0.01, 1]
  double translucency = 0.3;      // share of the albedo transmitted instead of reflected, [0, 1]
  // Leaves: measured Cabernet Sauvignon spectra (Helios' leaf library).
  Rgb leaf_reflectance{0.075f, 0.114f, 0.071f};
  Rgb leaf_transmittance{0.031f, 0.093f, 0.020f};
  double leaf_back = 1.3;          // abaxial (lower) face reflectance relative to the upper, [0.5, 3]
  double leaf_texture = 0.12;      // within-leaf relative variation (4 mm value noise), [0, 1]
  double vein_width = 0.0008;      // m, the main veins' width at the petiole, [0, 0.005]
  double vein_contrast = 0.6;      // relative reflectance gain on a vein, [0, 3]
  // Woody and ground parts.
  double wood_texture = 0.15;      // relative variation of stems and canes (2 mm noise), [0, 1]
  Rgb ground_reflectance{0.17f, 0.14f, 0.11f};
  double ground_below = 1.0;       // m, ground below the bunch's lowest point, [0.05, 10]
  double row_spacing = 2.5;        // m, between vine rows (0: no other rows), [0, 10]
  double vine_spacing = 1.2;       // m, along the row: the foliage repeated at this pitch (0: once), [0, 10]
  int rows_behind = 1;             // vine rows drawn behind the bunch's, [0, 4]
  int post_every = 0;              // vines between trellis posts in the row copies (0: none), [0, 20]
  double post_radius = 0.04;       // m, [0.01, 0.2]
};
const ParamTable<AppearanceParams>& appearance_param_table();

// What a renderer needs at a surface point: diffuse reflectance and transmittance,
// specular weight and roughness.
struct Material {
  Rgb albedo;          // diffuse reflectance, linear
  Rgb transmittance;   // diffuse transmittance (leaves; berries' translucency), linear
  double specular = 0; // Fresnel F0 of the specular lobe (0: none)
  double roughness = 1;
};

// Berry skin of base colour `base` (linear reflectance).
Material berry_material(const AppearanceParams& a, const Rgb& base);
// Leaf face at `point` (m, world) of a leaf whose centre is `centre`, one lobe tip at
// `tip` (the lobes every 72 deg, synth/foliage.cpp), per-leaf shade `shade` (the
// leaf's colour over the mean leaf colour), upper (adaxial) face or not.
Material leaf_material(const AppearanceParams& a, const Vec3& point, const Vec3& centre, const Vec3& tip,
                       const Vec3& normal, double shade, bool upper);
// Stems, canes and the cordon: their synth colour with a fixed surface variation.
Material wood_material(const AppearanceParams& a, const Vec3& point, const Rgb& colour);
// That variation at `point` (m, world): the factor on the colour, 1 + wood_texture x
// value noise of 2 mm cells, in [1 - wood_texture, 1 + wood_texture].
double wood_texture_factor(const AppearanceParams& a, const Vec3& point);
// Smooth value noise in [-1, 1] with cells of `cell` m, fixed to the surface.
double value_noise(const Vec3& point, double cell, std::uint64_t salt);

}  // namespace grapebench
