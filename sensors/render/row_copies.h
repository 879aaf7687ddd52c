// The rest of the vine row behind a scene: its foliage repeated every `vine_spacing`
// along the row (x) and in `rows_behind` rows at `row_spacing` behind it (+y: away
// from the cameras' side of the row, synth/foliage.h), mirrored every other vine so
// the copies do not read as one; trellis posts between vines. Only drawn: never in the
// exact labels or the truth.
#pragma once

#include <cstddef>

#include "sensors/render/appearance.h"
#include "synth/foliage.h"

namespace grapebench {

struct RowCopies {
  Foliage foliage;                  // every copy, without the one that is the scene
  std::size_t source_triangles = 0; // copy triangle t repeats the scene's triangle t % this
  std::size_t source_vertices = 0;  // and copy vertex v the scene's vertex v % this
};

// Three vines each side along the row; empty when the scene has no foliage. With
// `a.post_every`, trellis posts (Stems labelled Background, after the copies' canes)
// from `ground_z` (m) to the canopy's top, midway between two vines; never in the
// scene's own row beside its vine, where one could hide a labelled leaf.
RowCopies row_copies(const Foliage& scene_foliage, const AppearanceParams& a, double ground_z);

}  // namespace grapebench
