#include "bench/protocols/stereo_pair.h"

#include <gtest/gtest.h>

#include "synth/generate.h"
#include "synth/params.h"

namespace grapebench {
namespace {

// The stalk ends at the main body's first branch. A wing's side branches leave the
// wing near the peduncle, above it, and must not lift the stalk's lower end: the
// wing draws from its own stream, so the same seed gives the same main skeleton with
// and without it (found in review: they did lift it, labelling the bare rachis bunch).
TEST(StereoPair, AWingDoesNotMoveTheStalksLowerEnd) {
  BunchParams p = preset("table-red");
  int winged = 0;
  for (std::uint64_t seed = 0; seed < 2; ++seed) {
    p.wing_probability = 0;
    const double without = first_branch_height(generate_bunch(p, seed));
    p.wing_probability = 1;
    const Bunch b = generate_bunch(p, seed);
    if (b.wing < 0) continue;
    ++winged;
    // Its side branches start above the body's first branch, so the test can fail.
    double highest = -1;
    for (std::size_t i = 0; i < b.stems.size(); ++i) {
      if (b.stems[i].parent == b.wing && b.stems[i].part == Part::Rachis) highest = std::max(highest, b.stems[i].start.z());
    }
    EXPECT_GT(highest, without) << "seed " << seed;
    EXPECT_EQ(first_branch_height(b), without) << "seed " << seed;
    EXPECT_TRUE(on_wing(b, b.wing));
    EXPECT_FALSE(on_wing(b, b.peduncle));
  }
  EXPECT_EQ(winged, 2);
}

}  // namespace
}  // namespace grapebench
