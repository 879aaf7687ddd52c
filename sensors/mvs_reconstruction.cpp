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
                "sd of the matching's disparity error; depth sd z^2 sd / (f b), b the nearest other view")
          .real("outlier_fraction", "-", &P::outlier_fraction, 0, 1,
                "fraction of mismatched returns, with a uniform disparity error instead")
          .real("outlier_disparity", "px", &P::outlier_disparity, 0, 1000, "mismatches' disparity error bound");
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

FusedCloud mvs_reconstruction(const Scan& scan, const MvsNoiseParams& p, const FusionParams& fusion,
                              std::uint64_t seed, const std::vector<Eigen::Isometry3d>& poses) {
  const std::size_t nv = scan.views.size();
  if (!poses.empty() && poses.size() != nv)
    throw InputError("mvs reconstruction: " + std::to_string(poses.size()) + " poses for " + std::to_string(nv) + " views");
  if (nv < 2) throw InputError("mvs reconstruction: the pass needs at least two views (it has " + std::to_string(nv) + ")");
  std::vector<LabelledReturn> returns;
  for (std::size_t k = 0; k < nv; ++k) {
    const ScanView& v = scan.views[k];
    double b = std::numeric_limits<double>::infinity();
    for (std::size_t j = 0; j < nv; ++j) {
      if (j != k) b = std::min(b, (scan.views[j].camera.centre() - v.camera.centre()).norm());
    }
    if (!(b > 1e-6)) throw InputError("mvs reconstruction: views " + v.rig.name + " and another stand at one place");
    const double f = v.camera.K.fx;
    const Eigen::Isometry3d& pose = poses.empty() ? v.camera.pose : poses[k];
    const OrganisedCloud& c = v.cloud;
    for (std::size_t i = 0; i < c.size(); ++i) {
      if (!c.valid[i]) continue;
      const auto part = static_cast<Part>(c.label[i]);
      if (part == Part::Background || part == Part::None) continue;
      const Vec3 x = c.xyz[i].cast<double>();  // camera frame
      const double z = x.z();
      const double sd = z * z * p.disparity_sd / (f * b);
      // Along the ray: scale the point so its depth moves by the error.
      double z_new = z + sd * hashed_normal(derive_seed(seed, k), i);
      if (p.outlier_fraction > 0 && hashed_uniform(derive_seed(seed, k + nv), i) < p.outlier_fraction) {
        const double d = f * b / z + p.outlier_disparity * (2 * hashed_uniform(derive_seed(seed, k + 2 * nv), i) - 1);
        if (d < 0.5) continue;  // no match in front of the camera
        z_new = f * b / d;
      }
      returns.push_back({pose * (x * (z_new / z)), c.rgb[i], part, static_cast<int>(k), sd});
    }
  }
  return fuse_returns(returns, fusion);
}

}  // namespace grapebench
