// Leaves and canes around a hanging bunch: the vine-row scene of seed 003 (a robot
// passing a row of potted vines, clusters among foliage). They only occlude and fill
// the colour frame; the bunch's ground truth ignores them.
#pragma once

#include "synth/config.h"
#include "synth/param_table.h"
#include "synth/types.h"

#include <array>
#include <cstdint>
#include <vector>

namespace grapebench {

struct FoliageParams {
  int leaves = 40;                   // count, [0, 2000]
  double leaf_radius = 0.07;         // m, mean lobe tip radius, [0.01, 0.3]
  double leaf_radius_sd = 0.015;     // m, [0, 0.1]
  double row_half_length = 0.6;      // m, leaves and cordon span x in centre +- this, [0.05, 5]
  double canopy_depth = 0.3;         // m, leaves' y range (across the row), [0, 2]
  double canopy_below = 0.3;         // m, leaves reach this far below the bunch bottom, [0, 2]
  double canopy_above = 0.35;        // m, and this far above the cordon, [0, 2]
  double clearance = 0.01;           // m, leaves keep this gap to the bunch's berries, [0, 0.5]
  // Chance that a leaf drawn between the row's front (-y side, where the robot passes)
  // and the bunch, over its silhouette, is kept: 0 leaves the bunch's face clear.
  double occlusion = 0.3;            // [0, 1]
  double cordon_radius = 0.012;      // m, horizontal cane carrying the bunch, [0.002, 0.05]
  int shoots = 6;                    // vertical canes rising from the cordon, [0, 100]
  double shoot_radius = 0.006;       // m, [0.002, 0.05]
  Rgb leaf_colour{0.12f, 0.38f, 0.07f};   // linear RGB, varied per leaf
  double leaf_colour_sd = 0.15;      // relative, [0, 1]
  Rgb cane_colour{0.33f, 0.22f, 0.12f};
  // The trellis: pairs of foliage wires above the cordon on both faces of the canopy
  // (VSP), as thin cylinders labelled Background (not vine). 0 keeps the scenes
  // written before them unchanged.
  int wire_pairs = 0;                // count, [0, 4]
  double wire_spacing = 0.3;         // m, first pair above the cordon, then each pair above the last, [0.05, 1]
  double wire_radius = 0.00125;      // m, [0.0005, 0.005]
  Rgb trellis_colour{0.30f, 0.30f, 0.31f};  // linear RGB, wires and posts (weathered galvanised steel)
};
const ParamTable<FoliageParams>& foliage_param_table();  // scene section `foliage:`
FoliageParams read_foliage(const ConfigNode& node);

// Leaves as flat five-lobed polygons (triangle fans), canes as capped cylinders.
struct Foliage {
  std::vector<Vec3> vertices;                    // m, world
  std::vector<std::array<int, 3>> triangles;     // leaf triangles
  std::vector<Rgb> triangle_colour;              // per triangle
  std::vector<Stem> canes;                       // part = Cane (Background: trellis), no parent, berry -1
  Rgb cane_colour;
  Rgb trellis_colour;
  const Rgb& colour_of(const Stem& s) const { return s.part == Part::Background ? trellis_colour : cane_colour; }
  bool empty() const { return triangles.empty() && canes.empty(); }
};

// The cordon passes through the top of the peduncle along x (the row direction, as
// the robot-pass rig assumes); shoots rise from it; leaves fill the canopy box around
// the bunch without touching its berries; the wires, after the leaves (they draw
// nothing from the seed), run along x at y = cordon +- canopy_depth / 2. Deterministic
// in `seed`.
Foliage generate_foliage(const FoliageParams& p, const Bunch& bunch, std::uint64_t seed);

}  // namespace grapebench
