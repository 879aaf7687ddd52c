// Point-cloud filters of the papers' pre-processing (seed 000: pass-through, region
// growing, MLS, voxel grid; seed 002: statistical outlier removal, LCCP stalk removal).
// Each keeps track of where its output points come from, so the harness can score a
// filter against the ground-truth labels of the scan.
#pragma once

#include "algorithms/point_cloud.h"
#include "synth/param_table.h"

#include <string>
#include <vector>

namespace grapebench {

struct FilteredCloud {
  PointCloud points;                 // M x 3, m
  std::vector<Eigen::Index> source;  // M: the input row each output point is (or stands for)
  std::string notes;                 // what the filter did, one line
};

// Keeps the points inside an axis-aligned box of the cloud's own frame (PCL
// CropBox). Seed 000 clips "within a certain height range in the X and Y axis".
struct PassThroughParams {
  Vec3 min = Vec3::Constant(-1e9);  // m, box corner; each coordinate in [-1e9, 1e9]
  Vec3 max = Vec3::Constant(1e9);   // m, must exceed min on every axis
};
const ParamTable<PassThroughParams>& pass_through_param_table();
FilteredCloud pass_through(const PointCloud& cloud, const PassThroughParams& params);

// Euclidean cluster extraction (PCL EuclideanClusterExtraction): groups whose points
// are within `tolerance` of another point of the group; seed 003 Sect. II-B2 uses
// "a minimum Euclidean distance of 0.01 m between points from different clusters"
// and drops clusters of fewer than 300 points.
struct EuclideanClusterParams {
  double tolerance = 0.01;  // m, [1e-4, 1]; seed 003: 0.01 m
  int min_points = 300;     // points, [1, 1e8]; seed 003: 300
};
const ParamTable<EuclideanClusterParams>& euclidean_cluster_param_table();
// Row indices of each cluster, ascending; clusters largest first (ties: lowest first
// index first).
std::vector<std::vector<Eigen::Index>> euclidean_clusters(const PointCloud& cloud, const EuclideanClusterParams& params);

// Statistical outlier removal (seed 002 Sect. 2.1, PCL StatisticalOutlierRemoval): a
// point whose mean distance to its n nearest neighbours lies more than delta standard
// deviations above the cloud's mean of that distance is dropped. Seed 002 names n and
// delta without values; PCL's documented example values are the defaults.
struct OutlierRemovalParams {
  int mean_k = 50;          // n, neighbours, [1, 1000]
  double stddev_mul = 1.0;  // delta, standard deviations, [0, 100]
};
const ParamTable<OutlierRemovalParams>& outlier_removal_param_table();
FilteredCloud statistical_outlier_removal(const PointCloud& cloud, const OutlierRemovalParams& params);

// Voxel-grid downsampling (seed 000 Sect. "Point Cloud Registration", where PCL's
// VoxelGrid did it): one point per occupied voxel, the centroid of its points, in
// order of the voxel (x fastest); `source` is the voxel's point nearest its centroid.
// The grid starts half a leaf below the cloud's smallest coordinates (Open3D's
// VoxelDownSample), in double precision; a dense counting sort, not a k-d tree.
struct VoxelGridParams {
  double leaf = 0.002;  // m, voxel edge, [1e-4, 1]; seed 000 gives no value
};
const ParamTable<VoxelGridParams>& voxel_grid_param_table();
FilteredCloud voxel_grid(const PointCloud& cloud, const VoxelGridParams& params);

// Bunch/background separation by region growing on normals and curvature (seed 000
// Sect. "Point Cloud Segmentation", PCL RegionGrowing): regions grow from the
// smoothest points while neighbouring normals differ by less than the smoothness
// angle. Regions that are flat (plane-fit RMS below plane_rms) and large (extent above
// min_background_extent) are background (plate, wall, table) and removed; then the
// largest Euclidean cluster of what is left is kept, which drops stray returns.
struct RegionGrowingParams {
  int normal_k = 30;                    // neighbours for normals, [3, 500]
  int neighbours = 30;                  // region-growing neighbourhood, [3, 500]
  double smoothness_deg = 3.0;          // normal angle threshold, deg, [0.1, 90] (PCL example)
  double curvature = 1.0;               // curvature threshold for seeds, [0, 1] (PCL example)
  int min_region = 50;                  // smallest region, points, [1, 1e6]
  double plane_rms = 0.004;             // m, [1e-5, 0.1]: flatter regions are background
  double min_background_extent = 0.06;  // m, [0.001, 10]: and larger than this across
  double cluster_tolerance = 0.02;      // m, [0, 1]: Euclidean clustering of the rest (0 keeps all); 2 cm bridges Kinect gaps at 1 m
};
const ParamTable<RegionGrowingParams>& region_growing_param_table();
FilteredCloud region_growing_segmentation(const PointCloud& cloud, const RegionGrowingParams& params);

// Stalk removal by locally convex connected patches (seed 002 Sect. 2.2, Eqs. 5-6;
// Stein et al. 2014; PCL SupervoxelClustering + LCCPSegmentation). Seed 002 splits a
// fruit into pulp and stalk; a grape bunch splits into many convex berries, so a
// stalk starts at a segment that is thin and elongated (second principal extent below
// max_stalk_diameter, first above elongation x second) and reaches an end of the
// cloud along its major axis, and continues through thin segments touching it (within
// two voxels), up to max_stalk_segments segments in all.
struct LccpStalkParams {
  double voxel_resolution = 0.002;        // m, supervoxel voxel, [1e-4, 0.1]
  // Supervoxel sizes: seed 002 gives none. 2 mm voxels and 20 mm seeds removed the
  // peduncle best on Kinect scans at 0.8 m (scenes/seed002_kinect_bottom.yaml sweep).
  double seed_resolution = 0.02;          // m, supervoxel seed spacing, [1e-3, 0.5]
  double spatial_importance = 1.0;        // supervoxel weights, [0, 100]
  double normal_importance = 4.0;         // [0, 100]
  double concavity_tolerance_deg = 10.0;  // Eq. 5 angle tolerance, deg, [0, 90] (LCCP default)
  bool sanity_check = true;               // Eq. 6 (sanity criterion, theta)
  int min_segment_size = 0;               // supervoxels merged into neighbours below this, [0, 1000]
  double max_stalk_diameter = 0.02;       // m, extent across the stalk with noise and registration spread, [1e-3, 0.1]
  double elongation = 2.0;                // [1, 100]
  double end_band = 0.01;                 // m, a stalk segment reaches this close to the end, [0, 0.2]
  int max_stalk_segments = 8;             // [1, 20]
};
const ParamTable<LccpStalkParams>& lccp_stalk_param_table();
FilteredCloud lccp_stalk_removal(const PointCloud& cloud, const LccpStalkParams& params);

}  // namespace grapebench
