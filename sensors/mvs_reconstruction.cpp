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
          .real("fusion_voxel", "m", &P::fusion_voxel, 0.0005, 0.1,
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

FusedCloud mvs_reconstruction(const Scan& scan, const MvsNoiseParams& p, std::uint64_t seed) {
  const std::size_t nv = scan.views.size();
  if (nv < 2) throw InputError("mvs reconstruction: the pass needs at least two views (it has " + std::to_string(nv) + ")");
  FusedCloud out;
  std::map<std::tuple<std::int64_t, std::int64_t, std::int64_t>, Voxel> grid;  // ordered: a deterministic output
  for (std::size_t k = 0; k < nv; ++k) {
    const ScanView& v = scan.views[k];
    double b = std::numeric_limits<double>::infinity();
    for (std::size_t j = 0; j < nv; ++j) {
      if (j != k) b = std::min(b, (scan.views[j].camera.centre() - v.camera.centre()).norm());
    }
    if (!(b > 1e-6)) throw InputError("mvs reconstruction: views " + v.rig.name + " and another stand at one place");
    const double f = v.camera.K.fx;
    const OrganisedCloud& c = v.cloud;
    for (std::size_t i = 0; i < c.size(); ++i) {
      if (!c.valid[i]) continue;
      const auto part = static_cast<Part>(c.label[i]);
      if (part == Part::Background || part == Part::None) continue;
      ++out.returns;
      const Vec3 x = c.xyz[i].cast<double>();  // camera frame
      const double z = x.z();
      const double sd = z * z * p.disparity_sd / (f * b);
      // Along the ray: scale the point so its depth moves by the error.
      const double dz = sd * hashed_normal(derive_seed(seed, k), i);
      const Vec3 moved = v.camera.pose * (x * ((z + dz) / z));
      const auto key = std::make_tuple(static_cast<std::int64_t>(std::floor(moved.x() / p.fusion_voxel)),
                                       static_cast<std::int64_t>(std::floor(moved.y() / p.fusion_voxel)),
                                       static_cast<std::int64_t>(std::floor(moved.z() / p.fusion_voxel)));
      Voxel& vox = grid[key];
      vox.sum += moved;
      for (int ch = 0; ch < 3; ++ch) vox.rgb[static_cast<std::size_t>(ch)] += c.rgb[i][static_cast<std::size_t>(ch)];
      ++vox.parts[std::min<std::size_t>(static_cast<std::size_t>(part), 7)];
      vox.sd += sd;
      ++vox.n;
      const std::uint64_t bit = std::uint64_t{1} << (k % 64);
      if (!(vox.views & bit)) vox.views |= bit, ++vox.view_count;
    }
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

}  // namespace grapebench
