// A tight envelope of a bunch: CGAL's 3D alpha wrapping (Portaneri et al. 2022, "Alpha
// wrapping with an offset", ACM TOG 41(4)) of its surface. The convex hull bridges
// every gap; the wrap bridges only those a ball of radius `alpha` cannot enter, so
// solid / wrap measures how tightly the berries fill the bunch's own outline rather
// than its hull (issue 40's validation table).
#pragma once

#include "synth/types.h"

namespace grapebench {

struct AlphaWrapEnvelope {
  double volume = 0;       // m3: the wrap's volume less area x offset (its first-order offset)
  double wrap_volume = 0;  // m3: the wrap as CGAL returns it, `offset` outside the surface
  double area = 0;         // m2 of the wrap
  double alpha = 0, offset = 0;  // m, as used
  int faces = 0;
};

// Wraps the bunch's triangle mesh (icospheres of level 3, stems with 24 sides) with a
// carving ball of radius `alpha` in [0.5 mm, 50 mm] at `offset` in [alpha / 1000,
// alpha / 5] (m). The wrap is low on two counts: the mesh is inscribed in the exact
// solid (a level-3 icosphere holds 0.991 of its ball), and the wrap's facets, about
// alpha across (finer at smaller offsets), are chords. A lone berry wrapped with alpha
// its radius holds 0.983 of its ball at offset alpha / 100 and 0.943 at alpha / 30;
// on a class-9 table-red bunch solid / wrap moves by 0.003 between the two offsets.
// Throws InputError out of range or for a bunch without berries. Deterministic:
// CGAL's wrapping draws nothing at random.
AlphaWrapEnvelope alpha_wrap_envelope(const Bunch& bunch, double alpha, double offset);

}  // namespace grapebench
