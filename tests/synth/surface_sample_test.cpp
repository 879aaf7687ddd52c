#include "synth/surface_sample.h"

#include "solid_sampler.h"
#include "synth/config.h"
#include "synth/generate.h"
#include "synth/ground_truth.h"

#include <gtest/gtest.h>

#include <cmath>

namespace grapebench {
namespace {

// Divergence theorem: V = (1/3) integral over the boundary of (p - o) . n dA, for
// any origin o, estimated from the sample, with its Monte Carlo standard error (each
// candidate drawn taken as an independent term, zero when it was dropped).
struct Estimate {
  double volume = 0, standard_error = 0;
};
Estimate divergence_volume(const SurfaceSample& s, const Vec3& origin) {
  Estimate e;
  double squares = 0;
  for (std::size_t i = 0; i < s.points.size(); ++i) {
    const double term = s.weights[i] * (s.points[i] - origin).dot(s.normals[i]) / 3;
    e.volume += term;
    squares += term * term;
  }
  const auto n = static_cast<double>(s.candidates);
  e.standard_error = std::sqrt(std::max(0.0, squares - e.volume * e.volume / n));
  return e;
}

TEST(SurfaceSample, OneBallIsItsWholeSphere) {
  Bunch b;
  b.berries.push_back({Vec3(0.01, -0.02, 0.03), 0.008, {}, -1});
  const SurfaceSample s = sample_surface(b, 1e7, 3);
  ASSERT_EQ(s.points.size(), s.candidates);
  EXPECT_EQ(s.candidates, static_cast<std::size_t>(std::llround(1e7 * 4 * M_PI * 0.008 * 0.008)));
  for (std::size_t i = 0; i < s.points.size(); ++i) {
    EXPECT_NEAR((s.points[i] - b.berries[0].centre).norm(), 0.008, 1e-12);
    EXPECT_NEAR((s.points[i] - b.berries[0].centre).dot(s.normals[i]), 0.008, 1e-12);
  }
  EXPECT_NEAR(divergence_volume(s, b.berries[0].centre).volume / (4.0 / 3 * M_PI * std::pow(0.008, 3)), 1, 1e-12);
  // Uniform on the sphere: each coordinate has variance R^2 / 3, so the mean lies
  // within 4 standard errors of the centre.
  Vec3 mean = Vec3::Zero();
  for (const Vec3& p : s.points) mean += p / static_cast<double>(s.points.size());
  const double se = 0.008 / std::sqrt(3.0 * static_cast<double>(s.points.size()));
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(mean(k), b.berries[0].centre(k), 4 * se);
}

// Two overlapping balls: the points inside the other ball drop out, leaving the
// lens-free union, whose volume is 2 V_ball - V_lens.
TEST(SurfaceSample, TwoBallsLoseTheirCommonLens) {
  const double r = 0.01, d = 0.012;
  Bunch b;
  b.berries.push_back({Vec3(0, 0, 0), r, {}, -1});
  b.berries.push_back({Vec3(d, 0, 0), r, {}, -1});
  const SurfaceSample s = sample_surface(b, 2e7, 5);
  // Each cap beyond the plane x = d/2 has area 2 pi r h, h = r - d/2.
  const double kept = 1 - 2 * M_PI * r * (r - d / 2) / (4 * M_PI * r * r);
  EXPECT_NEAR(static_cast<double>(s.points.size()) / static_cast<double>(s.candidates), kept, 0.01);
  for (const Vec3& p : s.points) EXPECT_GE(std::min((p - b.berries[0].centre).norm(), (p - b.berries[1].centre).norm()), r - 1e-12);
  const double h = r - d / 2;
  const double lens = 2 * M_PI * h * h * (3 * r - h) / 3;
  const Estimate v = divergence_volume(s, Vec3(d / 2, 0, 0));
  EXPECT_NEAR(v.volume, 2 * 4.0 / 3 * M_PI * r * r * r - lens, 4 * v.standard_error);
  EXPECT_LT(v.standard_error, 0.004 * v.volume);
}

// A generated bunch: every point lies on the boundary of the solid (just outside
// along its normal, just inside against it, by the independent inside test of the
// Monte Carlo volume tests), and the divergence theorem gives the exact volume.
TEST(SurfaceSample, GeneratedBunchBoundaryAndVolume) {
  const BunchParams p = preset("table-red");
  const Bunch b = generate_bunch(p, 7);
  const SurfaceSample s = sample_surface(b, 6e6, 11);
  ASSERT_GT(s.points.size(), 50000u);
  ASSERT_EQ(s.normals.size(), s.points.size());
  ASSERT_EQ(s.parts.size(), s.points.size());
  const testing::SolidSampler solid(b);
  std::size_t outside_ok = 0, inside_ok = 0, stems = 0;
  for (std::size_t i = 0; i < s.points.size(); ++i) {
    EXPECT_NEAR(s.normals[i].norm(), 1, 1e-12);
    outside_ok += !solid.inside(s.points[i] + 1e-7 * s.normals[i]);
    inside_ok += solid.inside(s.points[i] - 1e-7 * s.normals[i]);
    stems += s.parts[i] != Part::Berry;
  }
  // A step of 1e-7 m crosses into another part only for a point drawn within 1e-7 m
  // of where two surfaces meet: a few in 1e5 at most.
  EXPECT_GT(static_cast<double>(outside_ok), (1 - 1e-4) * static_cast<double>(s.points.size()));
  EXPECT_GT(static_cast<double>(inside_ok), (1 - 1e-4) * static_cast<double>(s.points.size()));
  EXPECT_GT(stems, 0u);
  const GroundTruth truth = compute_ground_truth(b, p.density);
  const Estimate v = divergence_volume(s, 0.5 * (truth.bbox_min + truth.bbox_max));
  EXPECT_NEAR(v.volume, truth.volume.solid, 4 * v.standard_error);
  EXPECT_LT(v.standard_error, 0.004 * v.volume);
}

TEST(SurfaceSample, SeededAndDeterministic) {
  const Bunch b = generate_bunch(preset("table-red"), 3);
  const SurfaceSample a = sample_surface(b, 2e5, 1), again = sample_surface(b, 2e5, 1), other = sample_surface(b, 2e5, 2);
  ASSERT_EQ(a.points.size(), again.points.size());
  for (std::size_t i = 0; i < a.points.size(); ++i) ASSERT_EQ(a.points[i], again.points[i]);
  EXPECT_NE(a.points.front(), other.points.front());
}

TEST(SurfaceSample, RejectsBadDensity) {
  const Bunch b = generate_bunch(preset("table-red"), 3);
  for (const double d : {0.0, -1.0, std::nan(""), 2e9}) {
    try {
      sample_surface(b, d, 1);
      ADD_FAILURE() << "density " << d << " accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("density"), std::string::npos) << e.what();
    }
  }
  // In range per m2 but too many points for this bunch.
  EXPECT_THROW(sample_surface(b, 9e8, 1), InputError);
}

}  // namespace
}  // namespace grapebench
