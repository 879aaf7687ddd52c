// The stems' and canes' wood texture (appearance.h, wood_texture_factor) baked for the
// Cycles export (cycles_render.h), so the reference draws the same 2 mm pattern the
// fast renderer does: each cylinder unrolled into its own rectangle of an atlas, along
// its axis (x) and around it (y), each texel the texture factor at that surface point.
// cycles_scene.py samples it bilinearly, as Blender's linear interpolation does.
#pragma once

#include <cstdint>
#include <vector>

#include "sensors/render/appearance.h"
#include "synth/types.h"

namespace grapebench {

struct WoodAtlasPlacement {
  int x0 = 0, y0 = 0;     // the rectangle's first texel (y from the atlas's bottom row)
  int along = 1;          // texel steps along the axis: texel x0 + i is the point at i / along of it
  int around = 3;         // texel steps around: texel y0 + j is at angle -pi + 2 pi j / around
  Vec3 x_axis = Vec3::UnitX();  // unit, normal to the axis: angle 0; angle pi / 2 is axis x x_axis
};

struct WoodAtlas {
  int width = 0, height = 0;            // texels
  std::vector<std::uint16_t> factor;    // height x width, row 0 at the bottom; the factor f as (f - 1 + a) / (2 a) x 65535 for a = wood_texture
  std::vector<WoodAtlasPlacement> placement;  // one per cylinder, in its order
};

// `texel[i]` (m, > 0) is cylinder i's texel size; rectangles are (along + 1) x
// (around + 1) texels: the last column is the cylinder's end, the last row the seam at
// angle +pi again (drawn twice, so bilinear sampling never reads a neighbour). Packed
// in shelves, tallest first, into a width of at least 4096. The caps are not baked:
// Blender draws them with the side's rim texture drawn inwards. Throws
// std::invalid_argument on a degenerate cylinder (zero length or radius) or texel
// size, a side of 65535 texels or more, or more than 2^28 texels in all.
WoodAtlas wood_atlas(const std::vector<Stem>& cylinders, const std::vector<double>& texel, const AppearanceParams& a);

}  // namespace grapebench
