// Points drawn uniformly by area on the boundary of a bunch's solid (the union of its
// berries and stem cylinders), each with its exact outward normal: a cloud with no
// occlusion and no noise, which tests a surface reconstruction alone (a turntable
// scan cannot: the pockets between berries that no camera sees put a floor under
// every volume from it; sensors/visibility_hull.h).
#pragma once

#include "synth/types.h"

#include <cstdint>
#include <vector>

namespace grapebench {

struct SurfaceSample {
  std::vector<Vec3> points;   // m, on the boundary of the solid
  std::vector<Vec3> normals;  // unit, outward
  std::vector<Part> parts;    // which part's surface each point lies on
  // m2: the area each point stands for (its primitive's area over the candidates drawn
  // on it), so sum(weight) estimates the boundary's area and, by the divergence
  // theorem, sum(weight * p.n) / 3 the solid's volume.
  std::vector<double> weights;
  std::size_t candidates = 0;  // drawn on every primitive before those inside another part were dropped
};

// Draws round(density * area) candidates on each berry sphere and on each stem's
// lateral surface and end caps, and keeps those that lie inside no other primitive
// (closed tests, so the shared faces of stacked rachis segments and the ends buried in
// a parent or a berry drop out). `density` is in points per m2, (0, 1e9]; at most 5e7
// candidates in all. Deterministic for a seed. Throws InputError out of range.
SurfaceSample sample_surface(const Bunch& bunch, double density, std::uint64_t seed);

}  // namespace grapebench
