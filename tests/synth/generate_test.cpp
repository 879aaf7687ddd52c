#include "synth/generate.h"

#include "synth/ground_truth.h"
#include "synth/io.h"
#include "synth/mesh.h"
#include "synth/params.h"
#include "synth/rng.h"
#include "synth/stem_geometry.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>
#include <cstring>

namespace grapebench {
namespace {

class EveryPreset : public ::testing::TestWithParam<std::string> {};

// The generator's guarantee that the volume formula accounts for every contact.
TEST_P(EveryPreset, ContactsAreOnlyThoseTheFormulaAccountsFor) {
  for (double c : {0.0, 0.5, 1.0}) {
    BunchParams p = preset(GetParam());
    p.compactness = c;
    p.oiv_compactness = 0;  // a variety preset's class would override c
    for (std::uint64_t seed = 0; seed < 2; ++seed) {
      const Bunch b = generate_bunch(p, seed);  // throws when check_bunch finds a contact (as for every bunch)
      EXPECT_LE(berry_contacts(b).depth_max, c * p.max_press_depth * (1 + 1e-6) + 1e-9);
      EXPECT_GE(static_cast<int>(b.berries.size()), 1);
    }
  }
}

// The OIV classes and wings too: each keeps only the contacts the formula accounts
// for, and presses no deeper than its class sets.
TEST_P(EveryPreset, EveryOivClassAndWingKeepsOnlyTheContactsTheFormulaAccountsFor) {
  for (int oiv : {1, 5, 9}) {
    BunchParams p = preset(GetParam());
    p.oiv_compactness = oiv;
    p.wing_probability = oiv == 5 ? 0 : 1;
    const BunchParams q = oiv_compactness_params(p);
    for (std::uint64_t seed = 0; seed < 2; ++seed) {
      const Bunch b = generate_bunch(p, seed);  // throws when check_bunch finds a contact
      EXPECT_EQ(b.wing >= 0, p.wing_probability == 1) << GetParam() << " class " << oiv << " seed " << seed;
      const auto problems = check_bunch(b);
      EXPECT_TRUE(problems.empty()) << GetParam() << " class " << oiv << " seed " << seed << ": " << problems.front();
      EXPECT_LE(berry_contacts(b).depth_max, q.compactness * q.max_press_depth * (1 + 1e-6) + 1e-9);
    }
  }
}

TEST_P(EveryPreset, SameSeedSameBytesDifferentSeedDifferentBunch) {
  const BunchParams p = preset(GetParam());
  auto render = [&](std::uint64_t seed) {
    const Bunch b = generate_bunch(p, seed);
    const GroundTruth g = compute_ground_truth(b, p.density);
    const BunchRecord rec{GetParam(), seed, 0, p, {}};
    return ground_truth_json(b, g, rec).dump() + ply_bytes(bunch_mesh(b));
  };
  EXPECT_EQ(render(7), render(7));
  EXPECT_NE(render(7), render(8));
}

INSTANTIATE_TEST_SUITE_P(Presets, EveryPreset, ::testing::ValuesIn(preset_names()),
                         [](const auto& param_info) {
                           std::string n = param_info.param;
                           for (auto& c : n) c = c == '-' ? '_' : c;
                           return n;
                         });

// The bits of a bunch, FNV-1a over its berries' and stems' doubles.
std::uint64_t bunch_bits(const Bunch& b) {
  std::uint64_t h = 0xcbf29ce484222325ULL;
  const auto mix = [&h](double v) {
    unsigned char bytes[sizeof v];
    std::memcpy(bytes, &v, sizeof v);
    for (unsigned char c : bytes) h = (h ^ c) * 0x100000001b3ULL;
  };
  for (const auto& berry : b.berries) {
    for (int a = 0; a < 3; ++a) mix(berry.centre[a]);
    mix(berry.radius);
  }
  for (const auto& st : b.stems) {
    for (int a = 0; a < 3; ++a) mix(st.start[a]), mix(st.end[a]);
    mix(st.radius);
  }
  return h;
}

// The variety presets against their sources (docs/synth.md, "Variety presets"): over 4
// bunches, the mean bunch mass inside the published range of means and the mean length
// (vertical, without the peduncle) inside the published length where there is one; each
// keeps its class and wings. Deterministic; a generator change that moves a 4-bunch
// mean out fails it (the margins are printed).
TEST(VarietyPresets, MassAndLengthWithinThePublishedRanges) {
  struct Source {
    const char* name;
    double mass_lo, mass_hi;      // g
    double length_lo, length_hi;  // m; 0, 0 when none was found
    int oiv;
    double wings;
  };
  for (const Source& s : {Source{"red-globe", 650, 850, 0, 0, 5, 0.5},
                          Source{"cabernet-sauvignon", 73, 157, 0.12, 0.15, 5, 0.5},
                          Source{"summer-black-ga", 600, 900, 0.16, 0.23, 7, 0},
                          Source{"italia", 400, 700, 0.20, 0.22, 3, 1}}) {
    const BunchParams p = preset(s.name);
    EXPECT_EQ(p.oiv_compactness, s.oiv) << s.name;
    EXPECT_EQ(p.wing_probability, s.wings) << s.name;
    double mass = 0, length = 0;
    for (std::uint64_t seed = 0; seed < 4; ++seed) {
      const Bunch b = generate_bunch(p, seed);
      const GroundTruth g = compute_ground_truth(b, p.density);
      mass += g.mass / 4;
      length += g.height / 4;
    }
    std::printf("[variety] %-18s mass %.0f g in [%g, %g], length %.3f m in [%g, %g]\n", s.name, mass, s.mass_lo, s.mass_hi,
                length, s.length_lo, s.length_hi);
    EXPECT_GE(mass, s.mass_lo) << s.name;
    EXPECT_LE(mass, s.mass_hi) << s.name;
    if (s.length_hi > 0) {
      EXPECT_GE(length, s.length_lo) << s.name;
      EXPECT_LE(length, s.length_hi) << s.name;
    }
  }
}

// A seed names one bunch whatever compiled the generator: its draws are sequenced
// (the pedicels' jitter was drawn in a call's arguments, whose order GCC and clang
// take differently, so clang's builds grew other bunches). The bits were GCC's.
TEST(Generate, ASeedGivesTheSameBitsOnEveryCompiler) {
  EXPECT_EQ(bunch_bits(generate_bunch(preset("table-red"), 7)), 13821697721003150845ULL);
  EXPECT_EQ(bunch_bits(generate_bunch(preset("wine-red"), 20261122)), 8047212741813460536ULL);
}

TEST(CheckBunch, ReportsAStemThroughAForeignBerry) {
  Bunch b = generate_bunch(preset("table-red"), 1);
  ASSERT_TRUE(check_bunch(b).empty());
  // Move one berry onto the rachis axis: it now touches a rachis segment.
  b.berries[0].centre = Vec3(0, 0, -0.05);
  EXPECT_FALSE(check_bunch(b).empty());
}

TEST(GroundTruth, DimensionsAndEnvelopeAreConsistent) {
  const BunchParams p = preset("table-red");
  const Bunch b = generate_bunch(p, 3);
  const GroundTruth g = compute_ground_truth(b, p.density);
  EXPECT_EQ(g.berry_count, static_cast<int>(b.berries.size()));
  EXPECT_NEAR(g.mass, g.volume.solid * 1e6 * 1.1, 1e-9);
  EXPECT_GE(g.pca_extent[0], g.pca_extent[1] * 0.8);  // first axis has the largest variance
  EXPECT_LE(g.envelope_lower, g.envelope_upper);
  // The bracket is within 0.2 %, so the midpoint is within 0.1 % of the hull volume.
  EXPECT_LT((g.envelope_upper - g.envelope_lower) / g.envelope_volume, 0.002);
  EXPECT_GT(g.compactness, 0.1);
  EXPECT_LT(g.compactness, 1.0);
  EXPECT_GT(g.height_from_cutting_point, g.height * 0.9);
  EXPECT_NEAR((g.cutting_point - b.top).norm(), p.cutting_point_fraction * p.peduncle_length, 1e-12);
}

// OIV 204: solid / hull rises with the class; class 9 is denser than the continuous
// key's densest setting (compactness 1) and its berries are pressed (docs/synth.md,
// 16 table-red bunches: class 1 0.197, 5 0.339, 9 0.455, compactness 1 0.384; here 2).
TEST(OivCompactness, DensityRisesWithTheClassAndClassNineIsPressed) {
  struct Mean {
    double solid_over_hull = 0, in_contact = 0, depth = 0;
  };
  const auto mean_of = [](BunchParams p) {
    Mean m;
    constexpr int kBunches = 2;  // ASan time: 4 took 30 s
    for (std::uint64_t seed = 0; seed < kBunches; ++seed) {
      const GroundTruth g = compute_ground_truth(generate_bunch(p, 424242 + seed), p.density);
      m.solid_over_hull += g.compactness / kBunches;
      m.in_contact += g.berries_in_contact / kBunches;
      m.depth += g.contact_depth_mean / kBunches;
    }
    return m;
  };
  BunchParams p = preset("table-red");
  p.compactness = 1;
  const Mean densest_before = mean_of(p);
  p.oiv_compactness = 1;
  const Mean c1 = mean_of(p);
  p.oiv_compactness = 5;
  const Mean c5 = mean_of(p);
  p.oiv_compactness = 9;
  const Mean c9 = mean_of(p);
  EXPECT_LT(c1.solid_over_hull + 0.05, c5.solid_over_hull);
  EXPECT_LT(c5.solid_over_hull + 0.05, c9.solid_over_hull);
  EXPECT_GT(c9.solid_over_hull, densest_before.solid_over_hull + 0.03);
  EXPECT_GT(c9.depth, 0.2);  // contacts flattened to a fifth of the radius and more
  EXPECT_GT(c9.in_contact, 0.95);
  EXPECT_LT(c1.in_contact, 0.9);  // very loose: 29 % of the berries touch none (docs/synth.md)
  EXPECT_LT(c1.depth, 1e-6);  // touching at most: class 1 presses nothing
}

// A wing carries its share of the berries and makes the bunch less round about the
// vertical (docs/synth.md: horizontal extent ratio 0.88 without, 0.77 with, table-red).
TEST(Wing, CarriesItsShareAndBreaksTheRoundness) {
  BunchParams p = preset("table-red");
  double ratio_without = 0, ratio_with = 0, share = 0;
  constexpr int kBunches = 2;
  for (std::uint64_t seed = 0; seed < kBunches; ++seed) {
    p.wing_probability = 0;
    const Bunch round = generate_bunch(p, 424242 + seed);
    EXPECT_EQ(round.wing, -1);
    ratio_without += compute_ground_truth(round, p.density).horizontal_extent_ratio / kBunches;
    p.wing_probability = 1;
    const Bunch winged = generate_bunch(p, 424242 + seed);
    ASSERT_GE(winged.wing, 0);
    const GroundTruth g = compute_ground_truth(winged, p.density);
    EXPECT_NEAR(g.wing_berry_share, p.wing_share, 0.06);  // the body drops more berries than the wing
    share += g.wing_berry_share / kBunches;
    ratio_with += g.horizontal_extent_ratio / kBunches;
  }
  EXPECT_NEAR(share, p.wing_share, 0.03);
  EXPECT_LT(ratio_with, ratio_without - 0.05);
}

// The wing and the flat side draw from their own streams: at probability 0.5 the
// bunches that get neither are, bit for bit, those of probability 0.
TEST(Wing, ABunchWithoutAWingOrAFlatSideIsTheBunchItsSeedGaveBefore) {
  BunchParams p = preset("wine-red");
  int without = 0, winged = 0, flat = 0;
  // Seeds 1, 2, 4 at probability 0.5: a wing only, a flat side only, neither (seeds
  // 0-7 measured; 8 seeds cost 20 s under ASan).
  for (const std::uint64_t seed : {1, 2, 4}) {
    p.wing_probability = p.flat_side_probability = 0.5;
    const Bunch b = generate_bunch(p, seed);
    winged += b.wing >= 0;
    flat += b.flat_side_distance > 0;
    std::printf("[wing] seed %d: wing %d, flat side %d\n", static_cast<int>(seed), b.wing >= 0, b.flat_side_distance > 0);
    if (b.wing >= 0 || b.flat_side_distance > 0) continue;
    ++without;
    p.wing_probability = p.flat_side_probability = 0;
    EXPECT_EQ(bunch_bits(b), bunch_bits(generate_bunch(p, seed))) << "seed " << seed;
  }
  EXPECT_GT(without, 0);
  EXPECT_GT(winged, 0);
  EXPECT_GT(flat, 0);
}

// A bent main axis: the bend's segment leaves the segment above at the drawn angle
// (bend_angle within +-25 %), starting on its axis inside it (check_bunch's child
// rule); the segments below follow it coaxially and their branches start on them; at
// probability 0.5 a bunch the draw leaves straight is, bit for bit, the bunch of
// probability 0 (its own stream).
TEST(Bend, TheAxisTurnsAtTheDrawnAngleAndAStraightBunchIsUnchanged) {
  BunchParams p = preset("table-red");
  int bent = 0, straight = 0;
  for (const std::uint64_t seed : {0, 1, 2, 3}) {
    p.bend_probability = 0.5;
    const Bunch b = generate_bunch(p, seed);
    if (b.bend < 0) {
      ++straight;
      p.bend_probability = 0;
      EXPECT_EQ(bunch_bits(b), bunch_bits(generate_bunch(p, seed))) << "seed " << seed;
      continue;
    }
    ++bent;
    EXPECT_TRUE(check_bunch(b).empty()) << check_bunch(b).front();
    const Stem& s = b.stems[static_cast<std::size_t>(b.bend)];
    ASSERT_GE(s.parent, 0);
    const Stem& above = b.stems[static_cast<std::size_t>(s.parent)];
    EXPECT_EQ(s.part, Part::Rachis);
    EXPECT_EQ(above.part, Part::Rachis);
    EXPECT_EQ(s.stacked_on, -1);
    const double angle = compute_ground_truth(b, p.density).bend_angle;
    EXPECT_GE(angle, 0.75 * p.bend_angle - 1e-9) << "seed " << seed;
    EXPECT_LE(angle, 1.25 * p.bend_angle + 1e-9) << "seed " << seed;
    // It starts on the axis above, 1.1 r sin(angle) above that segment's end.
    EXPECT_LT(point_segment_distance(s.start, above.start, above.end), 1e-12);
    EXPECT_NEAR((s.start - above.end).norm(), 1.1 * s.radius * std::sin(angle * M_PI / 180), 1e-9);
    // The knee's volume is the exact junction overlap: against a local Monte Carlo
    // count in a cube about the joint (the whole bunch's sample cannot see it: the knee
    // is 0.01-0.03 cm3 against a standard error of 0.3-1 cm3).
    {
      const double h = 2 * above.radius, box = std::pow(2 * h, 3);
      Rng r(99 + seed);
      constexpr int kSamples = 1'000'000;
      int both = 0;
      for (int i = 0; i < kSamples; ++i) {
        const double x = r.uniform(-h, h), y = r.uniform(-h, h), z = r.uniform(-h, h);
        const Vec3 q = s.start + Vec3(x, y, z);
        both += inside_stem(s, q) && inside_stem(above, q);
      }
      const double frac = static_cast<double>(both) / kSamples;
      const double se = std::sqrt(frac * (1 - frac) / kSamples) * box;
      EXPECT_GT(both, 1000);
      EXPECT_NEAR(junction_overlap_volume(s, above), frac * box, 3 * se) << "seed " << seed;
    }
    const Vec3 d = (s.end - s.start).normalized();
    int below = 0, branches = 0;
    for (std::size_t i = 0; i < b.stems.size(); ++i) {
      const Stem& t = b.stems[i];
      if (t.stacked_on >= 0 && (b.stems[static_cast<std::size_t>(t.stacked_on)].end - t.start).norm() < 1e-12 &&
          std::abs((t.end - t.start).normalized().dot(d) - 1) < 1e-12) {
        ++below;
      }
      if (t.parent == b.bend && t.part == Part::Rachis) {
        ++branches;
        EXPECT_LT(point_segment_distance(t.start, s.start, s.end), 1e-9);
      }
    }
    EXPECT_GT(below + branches, 0) << "seed " << seed;  // something hangs on the bent part
  }
  EXPECT_GT(bent, 0);
  EXPECT_GT(straight, 0);
  // A rachis that does not taper cannot bend (the bent part starts inside the part
  // above): a named input error, not a silently straight bunch.
  p.bend_probability = 1;
  p.rachis_radius_bottom = p.rachis_radius_top;
  try {
    generate_bunch(p, 0);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("bend_probability"), std::string::npos) << e.what();
  }
}

// A flat side: its wall cuts `flat_side_depth` off the round bunch's reach towards it,
// the body's berries end behind it (the packing's last steps hold every constraint;
// the pedicel's rod may leave a berry a little past it), and the bunch is flatter
// (docs/synth.md: horizontal extent ratio 0.88 round, 0.70 at depth 0.5, table-red).
TEST(FlatSide, TheBodyStaysBehindTheWallAndTheBunchIsFlatter) {
  BunchParams p = preset("table-red");
  p.flat_side_depth = 0.5;
  double ratio_without = 0, ratio_with = 0;
  for (std::uint64_t seed = 0; seed < 2; ++seed) {
    p.flat_side_probability = 0;
    const Bunch round = generate_bunch(p, 424242 + seed);
    EXPECT_EQ(round.flat_side_distance, 0);
    ratio_without += compute_ground_truth(round, p.density).horizontal_extent_ratio / 2;
    p.flat_side_probability = 1;
    const Bunch b = generate_bunch(p, 424242 + seed);
    ASSERT_GT(b.flat_side_distance, 0);
    EXPECT_NEAR(b.flat_side_normal.norm(), 1, 1e-12);
    EXPECT_EQ(b.flat_side_normal.z(), 0);
    double farthest = -1, round_reach = -1;
    for (const Berry& be : b.berries) farthest = std::max(farthest, be.centre.dot(b.flat_side_normal) + be.radius);
    for (const Berry& be : round.berries) {
      round_reach = std::max(round_reach, be.centre.dot(b.flat_side_normal) + be.radius);
    }
    EXPECT_NEAR(b.flat_side_distance, 0.5 * round_reach, 1e-12) << "seed " << seed;
    EXPECT_LT(farthest, b.flat_side_distance + 0.1 * p.berry_radius_mean) << "seed " << seed;
    EXPECT_TRUE(check_bunch(b).empty());
    ratio_with += compute_ground_truth(b, p.density).horizontal_extent_ratio / 2;
  }
  EXPECT_LT(ratio_with, ratio_without - 0.08);
}

TEST(OivCompactness, ClassZeroChangesNothingAndTheRangeIsNamed) {
  const BunchParams p = preset("summer-black");
  EXPECT_EQ(bunch_param_table().to_json(oiv_compactness_params(p)).dump(), bunch_param_table().to_json(p).dump());
  BunchParams q = p;
  try {
    set_bunch_param(q, "oiv_compactness", "10");
    FAIL() << "expected an error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("oiv_compactness"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("[0, 9]"), std::string::npos) << e.what();
  }
}

TEST(Params, OutOfRangeAndCrossFieldErrorsNameTheKey) {
  BunchParams p = preset("wine-red");
  p.pedicel_radius = p.branch_radius * 2;
  try {
    validate_bunch_params(p, "scene.yaml:3");
    FAIL() << "expected an error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("pedicel_radius"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("scene.yaml:3"), std::string::npos) << e.what();
  }
  EXPECT_THROW(preset("concord"), InputError);
}

}  // namespace
}  // namespace grapebench
