#include "algorithms/stereo/luo2016_stereo.h"

#include <chrono>
#include <cmath>
#include <cstdio>

#include "algorithms/stereo/rectified_triangulation.h"

namespace grapebench {

namespace {

// Seconds since t0, and t0 moved to now (one stage's lap).
double lap(std::chrono::steady_clock::time_point& t0) {
  const auto t = std::chrono::steady_clock::now();
  const double s = std::chrono::duration<double>(t - t0).count();
  t0 = t;
  return s;
}

}  // namespace

namespace {

// Both images W x H x 3 of the same size, at least the matching window; a camera.
void require_pair(const StereoPair& pair, int window) {
  const auto fine = [&](const RgbImage& im) {
    return im.width >= window && im.height >= window &&
           im.data.size() == static_cast<std::size_t>(im.width) * static_cast<std::size_t>(im.height) * 3;
  };
  if (!fine(pair.left) || !fine(pair.right) || pair.left.width != pair.right.width ||
      pair.left.height != pair.right.height) {
    throw InputError("luo2016_stereo: the pair must be two RGB images of one size, at least " + std::to_string(window) +
                     " px a side (left " + std::to_string(pair.left.width) + " x " + std::to_string(pair.left.height) +
                     ", right " + std::to_string(pair.right.width) + " x " + std::to_string(pair.right.height) + ")");
  }
  if (!(pair.fx > 0) || !(pair.fy > 0) || !(pair.baseline > 0) ||
      !std::isfinite(pair.cx + pair.cy + pair.fx + pair.fy)) {
    throw InputError("luo2016_stereo: the camera needs fx, fy > 0 px, a finite principal point and a baseline > 0 m");
  }
}

}  // namespace

Luo2016Result luo2016_stereo(const StereoPair& pair, const Luo2016Params& p, const ClusterRegion* region,
                             const RgbImage* berry_image) {
  require_pair(pair, p.matching.window);
  Luo2016Result r;
  auto t0 = std::chrono::steady_clock::now();
  if (region && (region->width != pair.left.width || region->height != pair.left.height ||
                 region->mask.size() != static_cast<std::size_t>(region->width) * region->height ||
                 region->x0 < 0 || region->y0 < 0 || region->x1 >= region->width || region->y1 >= region->height))
    throw InputError("luo2016_stereo: the given cluster region (" + std::to_string(region->width) + " x " +
                     std::to_string(region->height) + ", box " + std::to_string(region->x0) + ".." +
                     std::to_string(region->x1) + " x " + std::to_string(region->y0) + ".." +
                     std::to_string(region->y1) + ") is not of the " + std::to_string(pair.left.width) + " x " +
                     std::to_string(pair.left.height) + " image");
  if (berry_image && (berry_image->width != pair.left.width || berry_image->height != pair.left.height ||
                      berry_image->data.size() != pair.left.data.size()))
    throw InputError("luo2016_stereo: the berry stage's image (" + std::to_string(berry_image->width) + " x " +
                     std::to_string(berry_image->height) + ") is not of the " + std::to_string(pair.left.width) +
                     " x " + std::to_string(pair.left.height) + " x 3 left image");
  r.region = region ? *region : segment_cluster(pair.left, p.segmentation);
  r.seconds_segmentation = lap(t0);
  if (!r.region.found()) {
    r.failure = "no cluster region";
    return r;
  }
  r.cut = detect_cutting_point(pair.left, r.region, p.cutting_point);
  r.seconds_cutting_point = lap(t0);
  if (!r.cut.found()) {
    r.failure = r.cut.failure;
    return r;
  }
  const GreyImage left = to_grey(pair.left), right = to_grey(pair.right);
  const NccMatch cut = ncc_disparity(left, right, r.cut.x, r.cut.y, pair.fx, pair.baseline, p.matching);
  if (!cut.ok()) {
    r.failure = "cutting point not matched: " + cut.failure;
    r.seconds_matching = lap(t0);
    return r;
  }
  r.cut_disparity = cut.disparity;
  r.cutting_point = triangulate_rectified(pair, r.cut.x, r.cut.y, cut.disparity);
  r.seconds_matching = lap(t0);
  // Eq. 6 needs the berries' depth before matching them; the paper does not say where
  // it comes from: the cutting point's.
  r.berries = detect_berries(berry_image ? *berry_image : pair.left, r.region, r.cutting_point.z(), pair.fx, p.berries);
  r.seconds_berries = lap(t0);
  for (const Detection& d : r.berries.berries) {
    const NccMatch m = ncc_disparity(left, right, d.circle.x, d.circle.y, pair.fx, pair.baseline, p.matching);
    if (!m.ok()) {
      r.berry_matched.push_back(-1);
      continue;
    }
    r.berry_matched.push_back(static_cast<int>(r.berry_points.size()));
    r.berry_points.push_back(triangulate_rectified(pair, d.circle.x, d.circle.y, m.disparity));
  }
  r.seconds_matching += lap(t0);
  if (r.berry_points.size() < 2) {
    r.failure = "fewer than 2 berries matched (" + std::to_string(r.berries.berries.size()) + " detected)";
    return r;
  }
  r.volume = revolved_bounding_volume(r.cutting_point, r.berry_points);
  return r;
}

ImageDetection cluster_detection(const ClusterRegion& r, double score) {
  ImageDetection d;
  d.category = "bunch";
  d.score = score;
  d.x = r.x0, d.y = r.y0, d.w = r.x1 - r.x0 + 1, d.h = r.y1 - r.y0 + 1;
  d.mask_x = r.x0, d.mask_y = r.y0, d.mask_w = r.x1 - r.x0 + 1, d.mask_h = r.y1 - r.y0 + 1;
  d.mask.resize(static_cast<std::size_t>(d.mask_w) * d.mask_h);
  for (int y = 0; y < d.mask_h; ++y)
    for (int x = 0; x < d.mask_w; ++x)
      d.mask[static_cast<std::size_t>(y) * d.mask_w + x] =
          r.mask[static_cast<std::size_t>(y + r.y0) * r.width + (x + r.x0)] ? 1 : 0;
  return d;
}

Estimate luo2016_estimate(const EstimatorInput& input, const Luo2016Params& p) {
  if (!input.stereo)
    throw InputError("luo2016_stereo: needs a stereo pair (protocol: stereo_pair, sensor: stereo_rgb)");
  const StereoPair& pair = *input.stereo;
  const StereoOracle* oracle = input.oracle.get();
  const bool given_region = oracle && !oracle->cluster.empty(), given_berries = oracle && !oracle->berry_edges.data.empty();
  ClusterRegion given;
  if (given_region) given = cluster_region_of_mask(oracle->cluster, pair.left.width, pair.left.height, p.segmentation);
  // A given region under min_cluster_px has area 0: "no cluster region", as a segmented one.
  const Luo2016Result r =
      luo2016_stereo(pair, p, given_region ? &given : nullptr, given_berries ? &oracle->berry_edges : nullptr);
  Estimate e;
  e.error = r.failure;
  if (r.cut.found() && r.cut_disparity > 0) e.points.emplace_back("cutting_point", r.cutting_point);
  e.detections = r.berries.berries;
  // The cluster region the later stages stand on: the protocol scores it (cluster_iou,
  // cluster_top_px), which is how a lost cutting point is traced to its stage.
  if (r.region.found()) e.instances.push_back(cluster_detection(r.region, 1));
  if (r.ok()) {
    e.values = {{Quantity::HangingHeight, r.volume.height},
                {Quantity::MaxDiameter, r.volume.max_diameter},
                {Quantity::Volume, r.volume.volume}};
  }
  // Deterministic diagnostics only (results.csv is byte-identical at any thread count);
  // the stage times stay in Luo2016Result.
  char notes[256];
  std::snprintf(notes, sizeof notes,
                "region %d px; lines %zu; berries %zu of %d circles (radius window %.1f-%.1f px), %zu matched; "
                "cut disparity %.2f px",
                r.region.area, r.cut.lines.size(), r.berries.berries.size(), r.berries.candidates,
                r.berries.window.r_min, r.berries.window.r_max, r.berry_points.size(), r.cut_disparity);
  e.notes = notes;
  return e;
}

const ParamTable<Luo2016Params>& luo2016_param_table() {
  using P = Luo2016Params;
  static const ParamTable<P> table =
      ParamTable<P>()
          .section("segmentation", &P::segmentation, cluster_segmentation_param_table(),
                   "colour component, Otsu and post-processing (seed 001 Sect. 2.2.2.1)")
          .section("cutting_point", &P::cutting_point, cutting_point_param_table(),
                   "peduncle ROI, bilateral filter, Canny, Hough lines (seed 001 Sect. 2.2.2.3)")
          .section("berries", &P::berries, berry_circle_param_table(),
                   "gradient Hough circles, refit and Eq. 7's rules (seed 001 Sect. 2.2.2.4)")
          .section("matching", &P::matching, ncc_param_table(), "zero-mean NCC along the row (seed 001 Sect. 2.2.3.1)");
  return table;
}

}  // namespace grapebench
