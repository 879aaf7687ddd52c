#include "synth/vine_row.h"

#include <algorithm>

#include "synth/rng.h"

namespace grapebench {

const ParamTable<VineRowParams>& vine_row_param_table() {
  using P = VineRowParams;
  static const ParamTable<P> table =
      ParamTable<P>()
          .integer("vines", "count", &P::vines, 1, 50, "vines along the row section (seed 004 Sect. 4.1: four)")
          .real("vine_spacing", "m", &P::vine_spacing, 0.2, 5, "distance between neighbouring vines")
          .integer("bunches_per_vine", "count", &P::bunches_per_vine, 1, 50, "bunches each vine carries")
          .real("bunch_spacing", "m", &P::bunch_spacing, 0.05, 2, "distance between a vine's bunches along x")
          .real("ripening", "-", &P::ripening, 0, 1,
                "fraction of berries turned (seed 004: green set 0; ripening set: colour changing)")
          .rgb("ripe_colour", &P::ripe_colour, "colour of turned berries (linear RGB)");
  return table;
}

std::vector<Vec3> vine_row_anchors(const VineRowParams& p) {
  std::vector<Vec3> out;
  for (int v = 0; v < p.vines; ++v) {
    const double vx = (v - 0.5 * (p.vines - 1)) * p.vine_spacing;
    for (int b = 0; b < p.bunches_per_vine; ++b) {
      const double x = vx + (b - 0.5 * (p.bunches_per_vine - 1)) * p.bunch_spacing;
      out.emplace_back(x, 0.0, 0.0);
    }
  }
  return out;
}

Bunch vine_row(const std::vector<Bunch>& bunches, const VineRowParams& p, std::uint64_t seed) {
  const std::vector<Vec3> anchors = vine_row_anchors(p);
  if (bunches.size() != anchors.size())
    throw InputError("vine_row: " + std::to_string(bunches.size()) + " bunches for " +
                     std::to_string(anchors.size()) + " places on the row");
  Bunch row;
  row.top = row.cutting_point = Vec3::Zero();
  row.peduncle = -1;
  Rng rng(derive_seed(seed, 0x719e));
  for (std::size_t k = 0; k < bunches.size(); ++k) {
    const Bunch& b = bunches[k];
    const Vec3 hang = b.peduncle >= 0 ? b.stems[static_cast<std::size_t>(b.peduncle)].end : b.top;
    const Vec3 shift = anchors[k] - hang;
    const int berry0 = static_cast<int>(row.berries.size()), stem0 = static_cast<int>(row.stems.size());
    for (Berry berry : b.berries) {
      berry.centre += shift;
      if (berry.pedicel >= 0) berry.pedicel += stem0;
      if (rng.uniform() < p.ripening) {
        const double shade = 1 + rng.normal(0, 0.1);
        berry.colour = {static_cast<float>(std::clamp(p.ripe_colour.r * shade, 0.0, 1.0)),
                        static_cast<float>(std::clamp(p.ripe_colour.g * shade, 0.0, 1.0)),
                        static_cast<float>(std::clamp(p.ripe_colour.b * shade, 0.0, 1.0))};
      }
      row.berries.push_back(berry);
    }
    for (Stem s : b.stems) {
      s.start += shift, s.end += shift;
      if (s.parent >= 0) s.parent += stem0;
      if (s.berry >= 0) s.berry += berry0;
      if (s.stacked_on >= 0) s.stacked_on += stem0;
      row.stems.push_back(s);
    }
    if (k == 0) row.stem_colour = b.stem_colour;
  }
  return row;
}

}  // namespace grapebench
