// Seed 001's system (Luo et al. 2016): from one rectified colour stereo pair, the 3D
// cutting point on the peduncle and the bounding volume of the cluster. Steps, each its
// own file pair: segmentation and geometry (cluster_segmentation), cutting point
// (cutting_point_detection), berries (berry_circles), NCC matching (ncc_disparity),
// triangulation (rectified_triangulation), bounding volume (revolved_bounding_volume).
#pragma once

#include <string>
#include <vector>

#include "algorithms/stereo/berry_circles.h"
#include "algorithms/segmentation/cluster_segmentation.h"
#include "algorithms/stereo/cutting_point_detection.h"
#include "algorithms/stereo/ncc_disparity.h"
#include "algorithms/stereo/revolved_bounding_volume.h"

namespace grapebench {

struct Luo2016Params {
  ClusterSegmentationParams segmentation;
  CuttingPointParams cutting_point;
  BerryCircleParams berries;
  NccParams matching;
};
const ParamTable<Luo2016Params>& luo2016_param_table();

struct Luo2016Result {
  // Empty when the cutting point and the bounding volume were found; else the first
  // stage that failed: "no cluster region", the cutting point's, "cutting point not
  // matched: ...", "fewer than 2 berries matched".
  std::string failure;
  ClusterRegion region;
  CuttingPointDetection cut;
  BerryCircles berries;
  double cut_disparity = 0;           // px
  Vec3 cutting_point = Vec3::Zero();  // m, left camera frame
  std::vector<Vec3> berry_points;     // m, the matched berries' front-surface centres
  std::vector<int> berry_matched;     // per detected berry: index into berry_points or -1
  RevolvedBoundingVolume volume;
  double seconds_segmentation = 0, seconds_cutting_point = 0, seconds_berries = 0, seconds_matching = 0;
  bool ok() const { return failure.empty(); }
};

// Throws InputError when the images differ in size, are not W x H x 3 or are smaller
// than the matching window, or the camera is degenerate. `region`: the cluster's, when
// the caller segmented the image already (luo2016_instances, one of several regions);
// null: the paper's segmentation, its largest region. `berry_image`: what the berry
// stage reads in place of the left image (the oracle ablation's berries redrawn from
// the exact labels; same size); null: the left image.
Luo2016Result luo2016_stereo(const StereoPair& pair, const Luo2016Params& p, const ClusterRegion* region = nullptr,
                             const RgbImage* berry_image = nullptr);

// The system as an estimator: the point "cutting_point" (left camera frame, m) when it
// was matched, the berry circles as detections, its cluster region as one "bunch"
// instance (mask) when it found one, and the bounding volume's hanging_height,
// max_diameter and volume; Estimate::error names the failed stage. Under the
// protocol's oracle ablation (input.oracle) the exact cluster pixels replace the
// segmentation and the exact berry outlines the berry stage's image, each when given.
// Throws InputError when the input has no stereo pair.
Estimate luo2016_estimate(const EstimatorInput& input, const Luo2016Params& p);

// A cluster region as an image detection of category "bunch": its box and its mask
// (the region's pixels, 0 / 1, on the box), with the given score.
ImageDetection cluster_detection(const ClusterRegion& r, double score);

}  // namespace grapebench
