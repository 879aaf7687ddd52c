// Seed 003's regions of interest (Sect. II-B2): automatic detection of grape clusters
// in one RGB-D frame by NDI colour clustering and Euclidean clustering (ROI_R^A), the
// box around a rough region's centre of mass (ROI_CM, Eq. 2), and the fine-tuning step
// that separates the grape cluster from the foliage left in a region. The manual path
// (ROI_R^M) takes the rough region from the ground-truth labels instead, so automatic
// and perfect detection can be compared; the harness builds it.
#pragma once

#include "algorithms/cloud/filters.h"
#include "algorithms/segmentation/ndi_kmeans.h"
#include "algorithms/point_cloud.h"

#include <string>
#include <vector>

namespace grapebench {

// Which colour clusters are grapes (seed 003 Sect. II-B2, fine tuning).
enum class GrapeColourRule {
  Red,    // centroid N > 0.2 and D > 0.2: the controlled outdoor (red) variety
  Black,  // centroid D < 0.2 and I > -0.05: the commercial vineyard (black) variety
};

struct Seed003RoiParams {
  int detection_clusters = 5;   // k of the first NDI k-means, [1, 64]; seed 003: 5, highest-N centroid kept
  int separation_clusters = 3;  // k of the grape/foliage k-means, [1, 64]; seed 003: 3
  GrapeColourRule rule = GrapeColourRule::Red;
  double n_min = 0.2;    // Red rule, centroid N above; seed 003: 0.2
  double d_min = 0.2;    // Red rule, centroid D above; seed 003: 0.2
  double d_max = 0.2;    // Black rule, centroid D below; seed 003: 0.2
  double i_min = -0.05;  // Black rule, centroid I above; seed 003: -0.05
  EuclideanClusterParams clusters;  // seed 003: 0.01 m, at least 300 points
  double roi_radius = 0.15;  // m, R of Eq. 2, [0.01, 2]; seed 003: 0.15 m
  std::uint64_t seed = 1;    // k-means++ draws
};
const ParamTable<Seed003RoiParams>& seed003_roi_param_table();

// Rows of the input cloud; ascending.
using Region = std::vector<Eigen::Index>;

struct Seed003Detection {
  std::vector<Region> regions;  // ROI_R^A, largest first
  std::string notes;            // cluster sizes and centroids chosen, one line
};

// Automatic rough detection on a pass-through-filtered frame: `cloud` N x 3 (m) and
// its colours `rgb` (N). Throws InputError when the sizes differ or a parameter is
// out of range; a frame with too few points for the clustering gives no region.
Seed003Detection detect_grape_regions(const PointCloud& cloud, const std::vector<Rgb8>& rgb,
                                      const Seed003RoiParams& params);

// Eq. 2: every point of the cloud inside the cube of half-edge R about the centre of
// mass of `rough` (strict inequalities, as written).
Region roi_from_centre_of_mass(const PointCloud& cloud, const Region& rough, double radius);

// Fine tuning: NDI k-means (separation_clusters) on the region, the clusters whose
// centroids pass the colour rule joined, then Euclidean clustering and the largest
// cluster kept (the tolerance of `clusters`, with no minimum size). Empty when no
// colour cluster passes the rule.
Region fine_tune_region(const PointCloud& cloud, const std::vector<Rgb8>& rgb, const Region& region,
                        const Seed003RoiParams& params);

}  // namespace grapebench
