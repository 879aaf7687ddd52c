// Acceptance: the analytic solid volume agrees with an independent Monte Carlo
// estimate (10^7 seeded samples, inside test straight from the primitives) within
// three standard errors, for the four legacy presets loose and compact (two variety
// presets at their own settings; the other two by hand, below), and for a hand-built
// bunch with pressed berries and pedicels entering berries.
#include "synth/generate.h"
#include "synth/ground_truth.h"
#include "synth/params.h"
#include "synth/solid_sampler.h"  // tests/synth

#include <gtest/gtest.h>

#include <cstdio>

namespace grapebench {
namespace {

constexpr long kSamples = 10'000'000;

void expect_agrees(const Bunch& b, std::uint64_t seed, const char* label) {
  ASSERT_TRUE(check_bunch(b).empty()) << check_bunch(b).front();
  const VolumeTerms v = solid_volume_terms(b);
  const auto mc = testing::SolidSampler(b).estimate(kSamples, seed);
  std::printf("[volume] %-28s analytic %.3f cm3  monte-carlo %.3f +- %.3f cm3  (%+.2f se)\n", label,
              v.solid * 1e6, mc.volume * 1e6, mc.standard_error * 1e6,
              (v.solid - mc.volume) / mc.standard_error);
  EXPECT_NEAR(v.solid, mc.volume, 3 * mc.standard_error);
}

struct Case {
  std::string preset;
  double compactness;
  int oiv = 0;  // OIV 204 class; 0 = the continuous compactness above
  bool wing = false;
  double flat = 0;  // flat_side_depth of a flat side; 0 = none
  bool bend = false;  // a bent main axis
};
void PrintTo(const Case& c, std::ostream* os) {
  *os << c.preset << " compactness " << c.compactness << " oiv " << c.oiv << (c.wing ? " winged" : "")
      << (c.flat > 0 ? " flat" : "") << (c.bend ? " bent" : "");
}

class PresetVolume : public ::testing::TestWithParam<Case> {};

std::string case_name(const ::testing::TestParamInfo<Case>& info) {
  const Case& c = info.param;
  std::string n = c.preset + (c.oiv ? "_oiv" + std::to_string(c.oiv) : c.compactness < 0.5 ? "_loose" : "_compact") +
                  (c.wing ? "_winged" : "") + (c.flat > 0 ? "_flat" + std::to_string(static_cast<int>(c.flat * 10)) : "") +
                  (c.bend ? "_bent" : "");
  for (auto& ch : n) ch = ch == '-' ? '_' : ch;
  return n;
}

TEST_P(PresetVolume, AnalyticMatchesMonteCarlo) {
  BunchParams p = preset(GetParam().preset);
  p.compactness = GetParam().compactness;
  p.oiv_compactness = GetParam().oiv;
  p.wing_probability = GetParam().wing ? 1 : 0;
  p.flat_side_probability = GetParam().flat > 0 ? 1 : 0;
  if (GetParam().flat > 0) p.flat_side_depth = GetParam().flat;
  p.bend_probability = GetParam().bend ? 1 : 0;
  const Bunch b = generate_bunch(p, 42);
  ASSERT_EQ(b.wing >= 0, GetParam().wing);
  ASSERT_EQ(b.bend >= 0, GetParam().bend);
  ASSERT_EQ(b.flat_side_distance > 0, GetParam().flat > 0);
  const std::string label = GetParam().preset + (GetParam().oiv ? " OIV " + std::to_string(GetParam().oiv)
                                                                 : " c=" + std::to_string(GetParam().compactness).substr(0, 4)) +
                            (GetParam().wing ? " winged" : "") + (GetParam().flat > 0 ? " flat" : "") +
                            (GetParam().bend ? " bent" : "");
  expect_agrees(b, 1234, label.c_str());
}

INSTANTIATE_TEST_SUITE_P(AllPresets, PresetVolume,
                         ::testing::Values(Case{"table-red", 0.15}, Case{"table-red", 0.95},
                                           Case{"wine-red", 0.15}, Case{"wine-red", 0.95},
                                           Case{"summer-black", 0.15}, Case{"summer-black", 0.95},
                                           Case{"green-table", 0.15}, Case{"green-table", 0.95},
                                           Case{"table-red", 0, 1, true}, Case{"table-red", 0, 9, true},
                                           Case{"wine-red", 0, 9}, Case{"summer-black", 0.95, 0, false, 0, true},
                                           // Two variety presets as they are: their class, and Italia's wing.
                                           Case{"italia", 0, 3, true}, Case{"summer-black-ga", 0, 7}),
                         case_name);

// Every OIV class, and flat sides, of table-red, and the other two variety presets: run by hand (docs/synth.md, "Pressed
// berries stay exact"), 2 s a case:
//   synth_tests --gtest_also_run_disabled_tests --gtest_filter='DISABLED_EveryClass/*'
INSTANTIATE_TEST_SUITE_P(DISABLED_EveryClass, PresetVolume,
                         ::testing::Values(Case{"table-red", 0, 1}, Case{"table-red", 0, 2}, Case{"table-red", 0, 3},
                                           Case{"table-red", 0, 4}, Case{"table-red", 0, 5}, Case{"table-red", 0, 6},
                                           Case{"table-red", 0, 7}, Case{"table-red", 0, 8}, Case{"table-red", 0, 9},
                                           Case{"table-red", 0, 5, false, 0.5}, Case{"table-red", 0, 9, true, 0.3},
                                           Case{"wine-red", 0, 9, false, 0.5}, Case{"table-red", 0, 9, false, 0, true},
                                           Case{"green-table", 0, 5, true, 0.3, true},
                                           Case{"red-globe", 0, 5, true}, Case{"cabernet-sauvignon", 0, 5, true}),
                         case_name);

// Three berries pressed together (a triple overlap), each on a pedicel entering it,
// the pedicels on one branch, the branch on a rachis hanging from a tilted peduncle.
Bunch hand_built() {
  Bunch b;
  const Vec3 up = Vec3(0.3, 0.1, 1).normalized();
  b.stems.push_back({-0.003 * up, 0.04 * up, 0.0035, Part::Peduncle});
  b.peduncle = 0;
  Stem rachis{Vec3(0, 0, 0), Vec3(0, 0, -0.06), 0.0025, Part::Rachis};
  rachis.parent = 0;
  b.stems.push_back(rachis);
  Stem branch{Vec3(0, 0, -0.03), Vec3(0.04, 0, -0.05), 0.0012, Part::Rachis};
  branch.parent = 1;
  b.stems.push_back(branch);
  const Vec3 bdir = (branch.end - branch.start).normalized();
  const Vec3 anchors[3] = {branch.start + 0.024 * bdir, branch.start + 0.032 * bdir, branch.start + 0.040 * bdir};
  const Vec3 centres[3] = {Vec3(0.024, 0.012, -0.058), Vec3(0.040, -0.010, -0.062), Vec3(0.036, 0.006, -0.075)};
  for (int i = 0; i < 3; ++i) {
    Berry berry{centres[i], 0.011, {}, -1};
    const Vec3 d = (centres[i] - anchors[i]).normalized();
    Stem ped{anchors[i], centres[i] - 0.5 * berry.radius * d, 0.0008, Part::Pedicel};
    ped.parent = 2;
    ped.berry = i;
    berry.pedicel = static_cast<int>(b.stems.size());
    b.stems.push_back(ped);
    b.berries.push_back(berry);
  }
  return b;
}

TEST(HandBuiltVolume, PressedBerriesAndPedicelsMatchMonteCarlo) {
  const Bunch b = hand_built();
  ASSERT_GT(berry_contacts(b).depth_max, 0.05) << "the case must contain pressed berries";
  const VolumeTerms v = solid_volume_terms(b);
  EXPECT_LT(v.berries_union, v.berries_sum);
  EXPECT_GT(v.pedicel_in_berry, 0);
  EXPECT_GT(v.junction_overlap, 0);
  expect_agrees(b, 99, "hand-built pressed");
}

}  // namespace
}  // namespace grapebench
