#include "synth/alpha_wrap_envelope.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "synth/config.h"

namespace grapebench {
namespace {

Bunch berries(std::initializer_list<Vec3> centres, double radius) {
  Bunch b;
  for (const Vec3& c : centres) {
    Berry berry;
    berry.centre = c;
    berry.radius = radius;
    b.berries.push_back(berry);
  }
  return b;
}

// A lone ball, wrapped as `grapebench synth --alpha-wrap` does (offset alpha / 100):
// less its offset, the wrap holds 0.983 of the ball. The level-3 icosphere it wraps
// holds 0.991; the wrap's facets, chords about alpha across, lose the rest. The raw
// wrap stands outside the ball (1.013: the offset outweighs the chords), and a coarser
// wrap (CGAL's default offset, alpha / 30) loses more to its chords (0.943).
TEST(AlphaWrapEnvelope, ALoneBerryIsWrappedToItsOwnVolume) {
  const double r = 0.01;
  const Bunch b = berries({Vec3::Zero()}, r);
  const AlphaWrapEnvelope e = alpha_wrap_envelope(b, r, r / 100);
  const double ball = 4.0 / 3 * M_PI * r * r * r;
  EXPECT_NEAR(e.volume / ball, 0.983, 0.008);
  EXPECT_LT(e.volume, 0.9914 * ball);  // below the inscribed mesh: the chords
  EXPECT_GT(e.wrap_volume, ball);
  EXPECT_NEAR(e.area, 4 * M_PI * r * r, 0.05 * 4 * M_PI * r * r);
  EXPECT_LT(alpha_wrap_envelope(b, r, r / 30).volume, e.volume - 0.02 * ball);
}

// Three berries in a row, touching: the hull (a capsule) bridges the notches between
// them; a small carving ball goes into them (the wrap is 1.04 of the solid at 0.3 r),
// a ball of twice a berry's radius does not (1.28 of the solid, 0.96 of the capsule).
TEST(AlphaWrapEnvelope, ASmallBallEntersTheNotchesTheHullBridges) {
  const double r = 0.01;
  const Bunch b = berries({Vec3(-2 * r, 0, 0), Vec3::Zero(), Vec3(2 * r, 0, 0)}, r);
  const double solid = 3 * 4.0 / 3 * M_PI * r * r * r;
  const double capsule = 4.0 / 3 * M_PI * r * r * r + M_PI * r * r * 4 * r;
  const double tight = alpha_wrap_envelope(b, 0.3 * r, 0.3 * r / 100).volume;
  const double loose = alpha_wrap_envelope(b, 2 * r, 2 * r / 100).volume;
  EXPECT_GT(tight, solid);
  EXPECT_LT(tight, 1.06 * solid);
  EXPECT_GT(loose, 1.2 * solid);
  EXPECT_LT(loose, capsule);
}

TEST(AlphaWrapEnvelope, OutOfRangeNamesTheRange) {
  const Bunch b = berries({Vec3::Zero()}, 0.01);
  for (const auto& [alpha, offset] : {std::pair{1e-4, 1e-5}, std::pair{0.06, 1e-3}, std::pair{0.01, 0.005},
                                      std::pair{std::nan(""), 1e-3}}) {
    try {
      alpha_wrap_envelope(b, alpha, offset);
      FAIL() << "expected an error for alpha " << alpha << ", offset " << offset;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("outside ["), std::string::npos) << e.what();
    }
  }
  EXPECT_THROW(alpha_wrap_envelope(Bunch{}, 0.01, 1e-3), InputError);
}

}  // namespace
}  // namespace grapebench
