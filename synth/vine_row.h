// Seed 004's scene (Dey et al. 2012, Sect. 4.1): a section of a vertically shoot-
// positioned vine row, several vines with their bunches hanging from one cordon along
// x in a leaf-pulled fruit zone; leaves and canes come from synth/foliage over the whole
// section. Berries are green (before ripening) or partly coloured (ripening).
#pragma once

#include <cstdint>
#include <vector>

#include "synth/config.h"
#include "synth/param_table.h"
#include "synth/types.h"

namespace grapebench {

struct VineRowParams {
  int vines = 4;               // along the row (seed 004: four vines in 15 ft), [1, 50]
  double vine_spacing = 0.9;   // m between neighbouring vines, [0.2, 5]
  int bunches_per_vine = 3;    // [1, 50]
  double bunch_spacing = 0.2;  // m between a vine's bunches along the cordon, [0.05, 2]
  // Fraction of berries that have turned (seed 004's ripening set: "changing colour");
  // 0 is the green set. Turned berries take `ripe_colour`, jittered like the preset's.
  double ripening = 0;                    // [0, 1]
  Rgb ripe_colour{0.16f, 0.05f, 0.15f};   // linear RGB
};
const ParamTable<VineRowParams>& vine_row_param_table();  // scene section `vine_row:`

// Where bunch k of the row hangs: the upper end of its peduncle, on the cordon (m).
// The row runs along x, centred on x = 0, with the cordon along the x axis.
std::vector<Vec3> vine_row_anchors(const VineRowParams& p);

// One Bunch holding every bunch of the row: each moved so its peduncle ends at its anchor,
// indices (pedicel, parent, berry, stacked_on) renumbered. The row has no peduncle of
// its own (-1) and its top at the origin, so synth/foliage centres the cordon, shoots
// and canopy on the row. Ripening recolours berries from `seed`'s own stream.
Bunch vine_row(const std::vector<Bunch>& bunches, const VineRowParams& p, std::uint64_t seed);

}  // namespace grapebench
