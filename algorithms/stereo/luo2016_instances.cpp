#include "algorithms/stereo/luo2016_instances.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace grapebench {

namespace {

// A berry's disc: the pixels whose centre lies within r of the circle's centre (OpenCV
// pixel centres at integers), clipped to the image.
ImageDetection berry_detection(const Detection& b, int width, int height) {
  ImageDetection d;
  d.category = "berry";
  d.score = b.score;
  const Circle& c = b.circle;
  const int x0 = std::max(0, static_cast<int>(std::ceil(c.x - c.r))), x1 = std::min(width - 1, static_cast<int>(std::floor(c.x + c.r)));
  const int y0 = std::max(0, static_cast<int>(std::ceil(c.y - c.r))), y1 = std::min(height - 1, static_cast<int>(std::floor(c.y + c.r)));
  // COCO box: pixel edges, so the centre pixel x spans [x, x + 1) there.
  d.x = c.x + 0.5 - c.r, d.y = c.y + 0.5 - c.r, d.w = 2 * c.r, d.h = 2 * c.r;
  if (x1 < x0 || y1 < y0) return d;
  d.mask_x = x0, d.mask_y = y0, d.mask_w = x1 - x0 + 1, d.mask_h = y1 - y0 + 1;
  d.mask.resize(static_cast<std::size_t>(d.mask_w) * d.mask_h);
  for (int y = y0; y <= y1; ++y)
    for (int x = x0; x <= x1; ++x)
      d.mask[static_cast<std::size_t>(y - y0) * d.mask_w + (x - x0)] = (x - c.x) * (x - c.x) + (y - c.y) * (y - c.y) <= c.r * c.r;
  return d;
}

}  // namespace

Estimate luo2016_instances(const EstimatorInput& input, const Luo2016InstancesParams& p) {
  if (!input.stereo || input.stereo->left.data.empty())
    throw InputError("luo2016_instances: needs a colour image (protocol: detection, sensor: stereo_rgb)");
  const StereoPair& pair = *input.stereo;
  const RgbImage& image = pair.left;
  const bool stereo = !pair.right.data.empty();
  if (p.depth <= 0 && !stereo)
    throw InputError("luo2016_instances: depth: 0 takes the berries' distance from the stereo pair, and the sensor "
                     "gives no right image (right_image: false): give depth in metres");
  Estimate e;
  std::vector<ClusterRegion> regions;
  if (p.regions == Luo2016InstancesParams::Regions::All) {
    regions = segment_clusters(image, p.system.segmentation);
  } else {
    ClusterRegion r = segment_cluster(image, p.system.segmentation);
    if (r.found()) regions.push_back(std::move(r));
  }
  double total = 0;
  for (const ClusterRegion& r : regions) total += r.area;
  int berries = 0, volumes = 0;
  for (const ClusterRegion& r : regions) {
    ImageDetection bunch = cluster_detection(r, r.area / total);
    double depth = p.depth;
    if (stereo) {
      // The paper's system on this region (its peduncle lies outside the region, above it).
      const Luo2016Result s = luo2016_stereo(pair, p.system, &r);
      if (s.ok()) bunch.volume = s.volume.volume, ++volumes;
      if (p.depth <= 0 && s.cut.found() && s.cut_disparity > 0) depth = s.cutting_point.z();
    }
    e.instances.push_back(std::move(bunch));
    if (depth <= 0) continue;
    for (const Detection& b : detect_berries(image, r, depth, pair.fx, p.system.berries).berries) {
      e.instances.push_back(berry_detection(b, image.width, image.height));
      ++berries;
    }
  }
  char notes[160];
  std::snprintf(notes, sizeof notes, "%zu regions, %d berries, %d volumes", regions.size(), berries, volumes);
  e.notes = notes;
  return e;
}

const ParamTable<Luo2016InstancesParams>& luo2016_instances_param_table() {
  using P = Luo2016InstancesParams;
  static const ParamTable<P> table =
      ParamTable<P>()
          .choice("regions", &P::regions, {{"largest", P::Regions::Largest}, {"all", P::Regions::All}},
                  "largest: the paper's one cluster per image (seed 001 Sect. 2.2.2.1); all: every region of "
                  "min_cluster_px, for images with several bunches")
          .real("depth", "m", &P::depth, 0, 10,
                "the berries' distance for Eq. 6's radius window; 0: the cutting point's from the stereo pair (seed "
                "001 Sect. 2.2.2.4)")
          .extend(&P::system, luo2016_param_table());
  return table;
}

}  // namespace grapebench
