#include "sensors/mvs_reconstruction.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <tuple>

#include "synth/rng.h"

namespace grapebench {

const ParamTable<MvsNoiseParams>& mvs_noise_param_table() {
  using P = MvsNoiseParams;
  static const ParamTable<P> table =
      ParamTable<P>()
          .real("disparity_sd", "px", &P::disparity_sd, 0, 20,
                "sd of the matching's disparity error; depth sd z^2 sd / (f b), b the baseline key or the nearest other view")
          .real("outlier_fraction", "-", &P::outlier_fraction, 0, 1,
                "fraction of mismatched returns, with a uniform disparity error instead")
          .real("outlier_disparity", "px", &P::outlier_disparity, 0, 1000, "mismatches' disparity error bound")
          .real("correlation_px", "px", &P::correlation_px, 0, 50,
                "correlation length of the disparity errors: pixels k px apart along a row or column correlate by "
                "exp(-k / correlation_px) (0: independent); summary.json's reconstruction gives SGBM's measured ones")
          .integer("edge_fattening_px", "px", &P::edge_fattening_px, 0, 10,
                   "returns within this many px behind a surface >= 3 % nearer may take its depth (window "
                   "matchers' foreground fattening); 0: off")
          .real("edge_fattening_fraction", "-", &P::edge_fattening_fraction, 0, 1,
                "probability that such a return takes the nearer depth (summary.json's reconstruction gives SGBM's "
                "outlier rate behind edges)")
          .when("edge_fattening_px > 0", [](const P& p) { return p.edge_fattening_px > 0; })
          .real("pixel_locking_px", "px", &P::pixel_locking_px, 0, 0.5,
                "amplitude of the sub-pixel bias -A sin(2 pi delta), delta the true disparity's fractional part "
                "(summary.json's reconstruction gives SGBM's measured one); 0: off")
          .real("baseline", "m", &P::baseline, 0, 10,
                "the matching's baseline b; 0: the distance to the nearest other view of the pass")
          .integer("window_px", "px", &P::window_px, 0, 10,
                   "each return takes the mean true disparity of the surfaces within this many px (a block "
                   "matcher's smoothing; SGBM's 5 px block: 2); 0: off");
  return table;
}

const ParamTable<FusionParams>& fusion_param_table() {
  using P = FusionParams;
  static const ParamTable<P> table =
      ParamTable<P>()
          .real("voxel", "m", &P::voxel, 0.0005, 0.1,
                "voxel edge of the fusion: one point per voxel (centroid, mean colour, majority label)")
          .integer("min_views", "count", &P::min_views, 1, 100,
                   "voxels seen by fewer views are dropped (multi-view consistency)");
  return table;
}

namespace {

struct Voxel {
  Vec3 sum = Vec3::Zero();
  std::array<double, 3> rgb{};
  std::array<int, 8> parts{};  // counts by Part value (0-6)
  double sd = 0;
  int n = 0;
  std::uint64_t views = 0;  // bit per view (first 64)
  int view_count = 0;
};

}  // namespace

std::vector<float> nearest_depth_within(const OrganisedCloud& c, int r) {
  if (r <= 0) return {};
  const int w = c.width, h = c.height;
  std::vector<float> row_min(c.size(), std::numeric_limits<float>::infinity()), out(c.size());
  for (int v = 0; v < h; ++v) {
    for (int u = 0; u < w; ++u) {
      float m = std::numeric_limits<float>::infinity();
      for (int du = std::max(0, u - r); du <= std::min(w - 1, u + r); ++du) {
        const std::size_t j = static_cast<std::size_t>(v) * static_cast<std::size_t>(w) + static_cast<std::size_t>(du);
        if (c.label[j] != static_cast<std::uint8_t>(Part::None) && c.true_depth[j] > 0) m = std::min(m, c.true_depth[j]);
      }
      row_min[static_cast<std::size_t>(v) * static_cast<std::size_t>(w) + static_cast<std::size_t>(u)] = m;
    }
  }
  for (int v = 0; v < h; ++v) {
    for (int u = 0; u < w; ++u) {
      float m = std::numeric_limits<float>::infinity();
      for (int dv = std::max(0, v - r); dv <= std::min(h - 1, v + r); ++dv)
        m = std::min(m, row_min[static_cast<std::size_t>(dv) * static_cast<std::size_t>(w) + static_cast<std::size_t>(u)]);
      out[static_cast<std::size_t>(v) * static_cast<std::size_t>(w) + static_cast<std::size_t>(u)] = m;
    }
  }
  return out;
}

std::vector<float> window_mean_depth(const OrganisedCloud& c, int r) {
  if (r <= 0) return {};
  const int w = c.width, h = c.height;
  const auto at = [w](int u, int v) { return static_cast<std::size_t>(v) * static_cast<std::size_t>(w) + static_cast<std::size_t>(u); };
  // Sums of 1 / z and of the count along rows, then along columns (separable box).
  std::vector<double> row_sum(c.size(), 0), row_count(c.size(), 0);
  for (int v = 0; v < h; ++v) {
    for (int u = 0; u < w; ++u) {
      double s = 0, n = 0;
      for (int du = std::max(0, u - r); du <= std::min(w - 1, u + r); ++du) {
        const std::size_t j = at(du, v);
        const auto part = static_cast<Part>(c.label[j]);
        if (part != Part::None && part != Part::Background && c.true_depth[j] > 0) s += 1.0 / c.true_depth[j], n += 1;
      }
      row_sum[at(u, v)] = s, row_count[at(u, v)] = n;
    }
  }
  std::vector<float> out(c.size());
  for (int v = 0; v < h; ++v) {
    for (int u = 0; u < w; ++u) {
      double s = 0, n = 0;
      for (int dv = std::max(0, v - r); dv <= std::min(h - 1, v + r); ++dv) s += row_sum[at(u, dv)], n += row_count[at(u, dv)];
      out[at(u, v)] = n > 0 ? static_cast<float>(n / s) : std::numeric_limits<float>::infinity();
    }
  }
  return out;
}

FusedCloud fuse_returns(const std::vector<LabelledReturn>& returns, const FusionParams& p) {
  FusedCloud out;
  std::map<std::tuple<std::int64_t, std::int64_t, std::int64_t>, Voxel> grid;  // ordered: a deterministic output
  for (const LabelledReturn& r : returns) {
    if (r.part == Part::Background || r.part == Part::None) continue;
    ++out.returns;
    const auto key = std::make_tuple(static_cast<std::int64_t>(std::floor(r.world.x() / p.voxel)),
                                     static_cast<std::int64_t>(std::floor(r.world.y() / p.voxel)),
                                     static_cast<std::int64_t>(std::floor(r.world.z() / p.voxel)));
    Voxel& vox = grid[key];
    vox.sum += r.world;
    for (std::size_t ch = 0; ch < 3; ++ch) vox.rgb[ch] += r.rgb[ch];
    ++vox.parts[std::min<std::size_t>(static_cast<std::size_t>(r.part), 7)];
    vox.sd += r.depth_sd;
    ++vox.n;
    const std::uint64_t bit = std::uint64_t{1} << (static_cast<unsigned>(r.view) % 64);
    if (!(vox.views & bit)) vox.views |= bit, ++vox.view_count;
  }
  for (const auto& [key, vox] : grid) {
    if (vox.view_count < p.min_views) continue;
    out.points.push_back(vox.sum / vox.n);
    out.colours.push_back({static_cast<std::uint8_t>(std::lround(vox.rgb[0] / vox.n)),
                           static_cast<std::uint8_t>(std::lround(vox.rgb[1] / vox.n)),
                           static_cast<std::uint8_t>(std::lround(vox.rgb[2] / vox.n))});
    const auto best = std::max_element(vox.parts.begin(), vox.parts.end());  // lowest Part value on ties
    out.labels.push_back(static_cast<Part>(best - vox.parts.begin()));
    out.depth_sd.push_back(vox.sd / vox.n);
  }
  return out;
}

std::vector<double> correlated_normal_field(int width, int height, double correlation_px, std::uint64_t seed) {
  const std::size_t w = static_cast<std::size_t>(std::max(width, 0)), h = static_cast<std::size_t>(std::max(height, 0));
  std::vector<double> field(w * h);
  for (std::size_t i = 0; i < field.size(); ++i) field[i] = hashed_normal(seed, i);
  if (!(correlation_px > 0) || field.empty()) return field;
  // A stationary AR(1) recursion y_i = a y_(i-1) + sqrt(1 - a^2) x_i, y_0 = x_0, keeps
  // unit variance and correlates lag k by a^k; along the rows, then along the columns.
  const double a = std::exp(-1 / correlation_px), c = std::sqrt(1 - a * a);
  for (std::size_t y = 0; y < h; ++y) {
    double* row = field.data() + y * w;
    for (std::size_t x = 1; x < w; ++x) row[x] = a * row[x - 1] + c * row[x];
  }
  for (std::size_t y = 1; y < h; ++y) {
    for (std::size_t x = 0; x < w; ++x) field[y * w + x] = a * field[(y - 1) * w + x] + c * field[y * w + x];
  }
  return field;
}

FusedCloud mvs_reconstruction(const Scan& scan, const MvsNoiseParams& p, const FusionParams& fusion,
                              std::uint64_t seed, const std::vector<Eigen::Isometry3d>& poses) {
  const std::size_t nv = scan.views.size();
  if (!poses.empty() && poses.size() != nv)
    throw InputError("mvs reconstruction: " + std::to_string(poses.size()) + " poses for " + std::to_string(nv) + " views");
  if (nv < 2) throw InputError("mvs reconstruction: the pass needs at least two views (it has " + std::to_string(nv) + ")");
  std::vector<LabelledReturn> returns;
  for (std::size_t k = 0; k < nv; ++k) {
    const ScanView& v = scan.views[k];
    double b = p.baseline > 0 ? p.baseline : std::numeric_limits<double>::infinity();
    for (std::size_t j = 0; j < nv && !(p.baseline > 0); ++j) {
      if (j != k) b = std::min(b, (scan.views[j].camera.centre() - v.camera.centre()).norm());
    }
    if (!(b > 1e-6)) throw InputError("mvs reconstruction: views " + v.rig.name + " and another stand at one place");
    const double f = v.camera.K.fx;
    const Eigen::Isometry3d& pose = poses.empty() ? v.camera.pose : poses[k];
    const OrganisedCloud& c = v.cloud;
    // Independent errors are drawn per return; only a correlated field is built whole.
    const std::uint64_t error_seed = derive_seed(seed, k);
    const std::vector<double> field = p.correlation_px > 0
                                          ? correlated_normal_field(c.width, c.height, p.correlation_px, error_seed)
                                          : std::vector<double>{};
    const std::vector<float> nearer = nearest_depth_within(c, p.edge_fattening_px);
    const std::vector<float> smoothed = window_mean_depth(c, p.window_px);
    for (std::size_t i = 0; i < c.size(); ++i) {
      if (!c.valid[i]) continue;
      const auto part = static_cast<Part>(c.label[i]);
      if (part == Part::Background || part == Part::None) continue;
      const Vec3 x = c.xyz[i].cast<double>();  // camera frame
      double z = smoothed.empty() ? x.z() : smoothed[i];
      if (!nearer.empty() && nearer[i] < kBehindEdgeDepthRatio * z &&
          hashed_uniform(derive_seed(seed, k + 3 * nv), i) < p.edge_fattening_fraction)
        z = nearer[i];  // the pixel's own ray, at the foreground's depth
      const double sd = z * z * p.disparity_sd / (f * b);
      // Along the ray: scale the point so its depth moves by the error.
      double z_new = z + sd * (field.empty() ? hashed_normal(error_seed, i) : field[i]);
      if (p.pixel_locking_px > 0) {  // disparity error -A sin(2 pi delta): depth z^2 / (f b) times its negative
        const double d = f * b / z;
        z_new += z * z / (f * b) * p.pixel_locking_px * std::sin(2 * M_PI * (d - std::floor(d)));
      }
      if (p.outlier_fraction > 0 && hashed_uniform(derive_seed(seed, k + nv), i) < p.outlier_fraction) {
        const double d = f * b / z + p.outlier_disparity * (2 * hashed_uniform(derive_seed(seed, k + 2 * nv), i) - 1);
        if (d < 0.5) continue;  // no match in front of the camera
        z_new = f * b / d;
      }
      returns.push_back({pose * (x * (z_new / x.z())), c.rgb[i], part, static_cast<int>(k), sd});
    }
  }
  return fuse_returns(returns, fusion);
}

}  // namespace grapebench
