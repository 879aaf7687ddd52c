// The procedural bunch generator.
#pragma once

#include "synth/params.h"
#include "synth/types.h"

#include <cstdint>
#include <string>
#include <vector>

namespace grapebench {

struct GenerationReport {
  int berries_requested = 0;  // drawn from [berry_count_min, berry_count_max]
  int berries_removed = 0;    // dropped because packing left them in a forbidden contact
  double rachis_length = 0;   // m
  int branches = 0;
};

// Builds one bunch: peduncle, a tapering rachis of stacked segments (bent once where
// bend_probability draws it), lateral branches shortening down the bunch, pedicels and
// berries packed against that tree by a position-based relaxation (gravity, pull
// towards the axis for compact bunches, bounded pressing between berries), with a wing
// and a flat side (a wall the body is packed against) when their probabilities draw
// them. Every contact that the
// volume formula does not account for is removed, so check_bunch() holds for the result.
// Same (params, seed) gives the same bunch bit for bit.
Bunch generate_bunch(const BunchParams& params, std::uint64_t seed,
                     GenerationReport* report = nullptr);

// The contacts the exact volume relies on (empty when all hold):
// - a stem with a parent starts on the parent's axis, its base disk inside the parent,
//   and is thinner than the parent; stacked rachis segments are coaxial and abut;
// - every other pair of stems is separated (no triple overlaps can exist);
// - a pedicel meets only its own berry, on an axis through the berry centre, starting
//   outside it and ending inside it before the far rim plane;
// - no other stem touches any berry.
// Berries may overlap each other in any pattern.
std::vector<std::string> check_bunch(const Bunch& bunch);

// True when stem `index` is the bunch's wing or hangs from it (its side branches and
// their pedicels): part of the bunch, never of the stalk above the first branch.
bool on_wing(const Bunch& bunch, int index);

}  // namespace grapebench
