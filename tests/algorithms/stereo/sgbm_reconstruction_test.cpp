// Seed 004's dense matching (OpenCV StereoSGBM with a left-right check) on a textured
// plane, drawn exactly and rendered with OSMesa by the stereo rig: depths within the
// stereo formula's error, colours from the left image.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "algorithms/stereo/sgbm_reconstruction.h"
#include "sensors/stereo_rgb.h"
#include "synth/foliage.h"
#include "synth/rng.h"

namespace grapebench {
namespace {

// A fronto-parallel plane at depth z carrying a smooth random texture (sum of sines),
// rendered exactly (point sampling at pixel centres) into a rectified pair.
StereoPair plane_pair(double z, double b) {
  StereoPair p;
  const int w = 320, h = 240;
  p.fx = p.fy = 400, p.cx = 159.5, p.cy = 119.5, p.baseline = b;
  Rng rng(5);
  struct Wave {
    double kx, ky, phase, amp;
  };
  std::vector<Wave> waves;
  for (int k = 0; k < 40; ++k)
    waves.push_back({rng.uniform(-300, 300), rng.uniform(-300, 300), rng.uniform(0, 2 * M_PI), rng.uniform(10, 25)});
  auto texture = [&](double x, double y) {  // plane coordinates, m
    double v = 128;
    for (const Wave& wv : waves) v += wv.amp * std::sin(wv.kx * x + wv.ky * y + wv.phase);
    return static_cast<std::uint8_t>(std::clamp(v, 0.0, 255.0));
  };
  for (RgbImage* im : {&p.left, &p.right}) {
    const double shift = im == &p.right ? b : 0.0;  // the right camera stands b to the right
    im->width = w, im->height = h;
    im->data.resize(static_cast<std::size_t>(w) * h * 3);
    for (int y = 0; y < h; ++y) {
      for (int x = 0; x < w; ++x) {
        const double px = (x - p.cx) * z / p.fx + shift, py = (y - p.cy) * z / p.fy;
        const std::uint8_t t = texture(px, py);
        std::uint8_t* q = im->data.data() + (static_cast<std::size_t>(y) * w + x) * 3;
        q[0] = t, q[1] = static_cast<std::uint8_t>(255 - t), q[2] = static_cast<std::uint8_t>(t / 2);
      }
    }
  }
  return p;
}

TEST(SgbmReconstruction, TexturedPlaneDepthsWithinTheStereoFormulasError) {
  const double z = 0.8, b = 0.05;
  const StereoPair pair = plane_pair(z, b);  // disparity f b / z = 25 px
  SgbmParams p;
  p.min_depth = 0.4, p.max_depth = 2.0;
  const SgbmCloud c = sgbm_reconstruction(pair, p);
  // Most pixels match. OpenCV leaves the left strip of min + number of disparities
  // unmatched: 10 + 48 px here (20-50 px searched, rounded up to a multiple of 16).
  EXPECT_GT(c.consistent, 0.8 * (320 - 58) * 240);
  std::vector<double> err;
  for (Eigen::Index i = 0; i < c.points.rows(); ++i) {
    err.push_back(c.points(i, 2) - z);
    ASSERT_GE(c.pixel[static_cast<std::size_t>(i)] % 320, 25u);  // never in the unmatched strip
  }
  std::sort(err.begin(), err.end());
  const double unit = z * z / (pair.fx * b);  // depth error of 1 px of disparity: 32 mm
  EXPECT_LT(std::abs(err[err.size() / 2]), 0.1 * unit);  // median within 0.1 px
  const double spread = 0.5 * (err[err.size() * 84 / 100] - err[err.size() * 16 / 100]);
  EXPECT_LT(spread, 0.3 * unit);  // about one sigma within 0.3 px
  // Colours are the left image's.
  const std::uint32_t px = c.pixel[0];
  EXPECT_EQ(c.colours[0][0], pair.left.data[3 * px]);
  // Lateral position from the principal point and the depth.
  const std::size_t mid = c.points.rows() / 2;
  const double u = c.pixel[mid] % 320;
  EXPECT_NEAR(c.points(static_cast<Eigen::Index>(mid), 0), (u - pair.cx) * c.points(static_cast<Eigen::Index>(mid), 2) / pair.fx,
              1e-9);
}

// A wall of textured leaf (the rig's leaf texture, 3 mm cells) at y = 0, facing a
// camera at distance z: 1 m x 0.7 m of 10 mm squares, each two leaf triangles.
Foliage leaf_wall() {
  Foliage f;
  const int nx = 100, nz = 70;
  for (int i = 0; i <= nx; ++i)
    for (int k = 0; k <= nz; ++k) f.vertices.push_back(Vec3(-0.5 + 0.01 * i, 0, -0.35 + 0.01 * k));
  const auto at = [&](int i, int k) { return i * (nz + 1) + k; };
  for (int i = 0; i < nx; ++i) {
    for (int k = 0; k < nz; ++k) {
      f.triangles.push_back({at(i, k), at(i + 1, k), at(i + 1, k + 1)});
      f.triangles.push_back({at(i, k), at(i + 1, k + 1), at(i, k + 1)});
    }
  }
  f.triangle_colour.assign(f.triangles.size(), Rgb{0.25f, 0.5f, 0.15f});
  return f;
}

// The stereo rig's rendered pair of a scene holding only `wall`, seen from (0, -z, 0)
// toward the origin, with seed 004's leaf texture; the left frame keeps the exact depths.
struct RenderedPair {
  OrganisedCloud frame;
  StereoPair pair;
};
RenderedPair rendered_pair(const Foliage& wall, double z) {
  const RayScene scene(Bunch{}, std::nullopt, wall);
  StereoRgbParams rp;  // seed 001's rig: 800 x 600, 1000 px focal length, 5 cm baseline
  rp.leaf_texture = 0.4, rp.texture_cells = 4;
  rp.background = StereoRgbParams::Background::Plain;
  const StereoRgb rig(rp);
  RenderedPair r;
  r.frame = rig.capture(scene, look_at(Vec3(0, -z, 0), Vec3::Zero()), 3);
  const Intrinsics K = rig.intrinsics();
  r.pair.fx = K.fx, r.pair.fy = K.fy, r.pair.cx = K.opencv_cx(), r.pair.cy = K.opencv_cy();
  r.pair.baseline = r.frame.baseline;
  r.pair.left = {r.frame.width, r.frame.height, r.frame.left_image};
  r.pair.right = {r.frame.width, r.frame.height, r.frame.right_image};
  return r;
}

TEST(SgbmReconstruction, RenderedTexturedPlaneDepthsWithinTheStereoFormulasError) {
  const double z = 0.8;
  const RenderedPair r = rendered_pair(leaf_wall(), z);
  const StereoPair& pair = r.pair;
  SgbmParams p;  // the protocol's defaults
  const SgbmCloud c = sgbm_reconstruction(pair, p);
  std::vector<double> err;
  for (Eigen::Index i = 0; i < c.points.rows(); ++i) err.push_back(c.points(i, 2) - z);
  std::sort(err.begin(), err.end());
  const double unit = z * z / (pair.fx * pair.baseline);  // depth error of 1 px of disparity: 12.8 mm
  const double median = err[err.size() / 2] / unit;
  const double spread = 0.5 * (err[err.size() * 84 / 100] - err[err.size() * 16 / 100]) / unit;
  std::size_t far = 0;  // off by more than 1 px
  for (double e : err) far += std::abs(e) > unit;
  const double searched = pair.fx * pair.baseline / p.min_depth;  // the unmatched left strip is at most this wide
  const double matchable = (r.frame.width - searched) * r.frame.height;
  std::printf("[sgbm] rendered plane: %zu points (%.1f %% of the matchable area), median %.3f px, sd %.3f px, %.2f %% beyond 1 px\n",
              err.size(), 100.0 * err.size() / matchable, median, spread, 100.0 * far / err.size());
  EXPECT_GT(static_cast<double>(err.size()), 0.8 * matchable);
  EXPECT_LT(std::abs(median), 0.1);  // px of disparity
  EXPECT_LT(spread, 0.3);
  EXPECT_LT(static_cast<double>(far), 0.01 * err.size());
  // Colours are the left image's.
  EXPECT_EQ(c.colours[0][1], pair.left.data[3 * c.pixel[0] + 1]);
}

// Pixel locking, the noise model's pixel_locking_px: on the same wall turned 25 deg
// (disparities 16 px apart across the image), sub-pixel disparities are drawn toward
// whole pixels. The error's mean is negative where the true disparity's fractional
// part delta is 0.15-0.35 and positive at 0.65-0.85; its least-squares amplitude
// A in e = -A sin(2 pi delta) (matches within 1 px) measured 0.13 px.
TEST(SgbmReconstruction, SubpixelDisparitiesOfARenderedSlantedPlaneLockTowardWholePixels) {
  Foliage wall = leaf_wall();
  const Eigen::AngleAxisd turn(25 * M_PI / 180, Vec3::UnitZ());
  for (Vec3& v : wall.vertices) v = turn * v;
  const RenderedPair r = rendered_pair(wall, 0.8);
  const SgbmCloud c = sgbm_reconstruction(r.pair, SgbmParams{});
  const double fb = r.pair.fx * r.pair.baseline;
  double es = 0, ss = 0, low = 0, n_low = 0, high = 0, n_high = 0;
  for (Eigen::Index i = 0; i < c.points.rows(); ++i) {
    const double truth = r.frame.truth(c.pixel[static_cast<std::size_t>(i)]);
    ASSERT_GT(truth, 0);
    const double d = fb / truth, e = fb / c.points(i, 2) - d, delta = d - std::floor(d);
    if (std::abs(e) > 1) continue;
    const double s = -std::sin(2 * M_PI * delta);
    es += e * s, ss += s * s;
    if (delta > 0.15 && delta < 0.35) low += e, n_low += 1;
    if (delta > 0.65 && delta < 0.85) high += e, n_high += 1;
  }
  const double amplitude = es / ss;
  std::printf("[sgbm] slanted plane: locking amplitude %.3f px; mean error %.3f px at delta 0.15-0.35, %.3f px at 0.65-0.85\n",
              amplitude, low / n_low, high / n_high);
  EXPECT_GT(amplitude, 0.05);
  EXPECT_LT(amplitude, 0.25);
  EXPECT_LT(low / n_low, -0.03);
  EXPECT_GT(high / n_high, 0.03);
}

TEST(SgbmReconstruction, RefusesBadPairs) {
  StereoPair pair = plane_pair(0.8, 0.05);
  pair.right.width = 100;
  EXPECT_THROW(sgbm_reconstruction(pair, SgbmParams{}), InputError);
  pair = plane_pair(0.8, 0.05);
  pair.baseline = 0;
  EXPECT_THROW(sgbm_reconstruction(pair, SgbmParams{}), InputError);
  pair = plane_pair(0.8, 0.05);
  SgbmParams p;
  p.min_depth = 0.01;  // disparities up to 2000 px: more than the image
  EXPECT_THROW(sgbm_reconstruction(pair, p), InputError);
}

}  // namespace
}  // namespace grapebench
