#include "algorithms/cloud/filters.h"

#include <pcl/features/normal_3d.h>
#include <pcl/filters/crop_box.h>
#include <pcl/filters/statistical_outlier_removal.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/search/kdtree.h>
#include <pcl/segmentation/extract_clusters.h>
#include <pcl/segmentation/lccp_segmentation.h>
#include <pcl/segmentation/region_growing.h>
#include <pcl/segmentation/supervoxel_clustering.h>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>

namespace grapebench {

namespace {

using Cloud = pcl::PointCloud<pcl::PointXYZ>;

// PCL works in single precision: points are shifted by `centre` (the cloud's mean) so
// float keeps micrometres.
Cloud::Ptr to_pcl(const PointCloud& cloud, Eigen::RowVector3d& centre) {
  centre = cloud.colwise().mean();
  auto out = pcl::make_shared<Cloud>();
  out->resize(static_cast<std::size_t>(cloud.rows()));
  for (Eigen::Index i = 0; i < cloud.rows(); ++i) {
    const Eigen::RowVector3d q = cloud.row(i) - centre;
    (*out)[static_cast<std::size_t>(i)] = pcl::PointXYZ(static_cast<float>(q(0)), static_cast<float>(q(1)), static_cast<float>(q(2)));
  }
  return out;
}

FilteredCloud subset(const PointCloud& cloud, std::vector<Eigen::Index> keep, std::string notes) {
  std::sort(keep.begin(), keep.end());
  FilteredCloud f;
  f.points.resize(static_cast<Eigen::Index>(keep.size()), 3);
  for (std::size_t k = 0; k < keep.size(); ++k) f.points.row(static_cast<Eigen::Index>(k)) = cloud.row(keep[k]);
  f.source = std::move(keep);
  f.notes = std::move(notes);
  return f;
}

std::vector<Eigen::Index> to_rows(const pcl::Indices& idx) { return {idx.begin(), idx.end()}; }

// Principal extents (largest first) and the major axis of some rows of a cloud.
struct Spread {
  Vec3 extent = Vec3::Zero();
  Vec3 axis = Vec3::UnitX();
  double plane_rms = 0;  // RMS distance to the best-fit plane, m
};
Spread spread(const PointCloud& cloud, const std::vector<Eigen::Index>& rows) {
  Spread s;
  if (rows.size() < 3) return s;
  Vec3 mean = Vec3::Zero();
  for (auto r : rows) mean += cloud.row(r).transpose();
  mean /= static_cast<double>(rows.size());
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (auto r : rows) {
    const Vec3 d = cloud.row(r).transpose() - mean;
    cov += d * d.transpose();
  }
  cov /= static_cast<double>(rows.size());
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
  s.plane_rms = std::sqrt(std::max(0.0, eig.eigenvalues()(0)));
  s.axis = eig.eigenvectors().col(2);
  for (int k = 0; k < 3; ++k) {
    const Vec3 u = eig.eigenvectors().col(2 - k);
    double lo = 1e300, hi = -1e300;
    for (auto r : rows) {
      const double t = cloud.row(r).dot(u);
      lo = std::min(lo, t);
      hi = std::max(hi, t);
    }
    s.extent(k) = hi - lo;
  }
  return s;
}

}  // namespace

FilteredCloud pass_through(const PointCloud& cloud, const PassThroughParams& p) {
  require_points(cloud, 0, "pass_through");
  for (int k = 0; k < 3; ++k) {
    if (!(p.min(k) < p.max(k))) throw InputError("pass_through: min must be below max on every axis (x, y, z)");
  }
  std::vector<Eigen::Index> keep;
  for (Eigen::Index i = 0; i < cloud.rows(); ++i) {
    const Vec3 q = cloud.row(i).transpose();
    if ((q.array() >= p.min.array()).all() && (q.array() <= p.max.array()).all()) keep.push_back(i);
  }
  const auto n = keep.size();
  return subset(cloud, std::move(keep), "kept " + std::to_string(n) + " of " + std::to_string(cloud.rows()) + " points in the box");
}

FilteredCloud statistical_outlier_removal(const PointCloud& cloud, const OutlierRemovalParams& p) {
  require_points(cloud, 2, "statistical_outlier_removal");
  check_range(p.mean_k, 1, 1000, "statistical_outlier_removal", "mean_k");
  check_range(p.stddev_mul, 0, 100, "statistical_outlier_removal", "stddev_mul");
  Eigen::RowVector3d centre;
  const auto in = to_pcl(cloud, centre);
  pcl::StatisticalOutlierRemoval<pcl::PointXYZ> sor;
  sor.setInputCloud(in);
  sor.setMeanK(p.mean_k);
  sor.setStddevMulThresh(p.stddev_mul);
  pcl::Indices idx;
  sor.filter(idx);
  const auto n = idx.size();
  return subset(cloud, to_rows(idx), "removed " + std::to_string(cloud.rows() - static_cast<Eigen::Index>(n)) + " outliers");
}

FilteredCloud voxel_grid(const PointCloud& cloud, const VoxelGridParams& p) {
  require_points(cloud, 1, "voxel_grid");
  check_range(p.leaf, 1e-4, 1, "voxel_grid", "leaf", " m");
  // The grid of Open3D's VoxelDownSample: cells start half a leaf below the cloud's
  // smallest coordinates, so both libraries keep the same voxels.
  const Eigen::RowVector3d lo = cloud.colwise().minCoeff().array() - 0.5 * p.leaf;
  const Eigen::RowVector3d span = cloud.colwise().maxCoeff() - lo;
  Eigen::Array<std::uint64_t, 1, 3> dims;
  for (int a = 0; a < 3; ++a) dims(a) = static_cast<std::uint64_t>(std::floor(span(a) / p.leaf)) + 1;
  if ((span.array() / p.leaf + 1).prod() > 9e18) throw InputError("voxel_grid: the cloud spans too many voxels of this leaf");
  const auto n = static_cast<std::size_t>(cloud.rows());
  // Each point's cell as one number, x fastest.
  std::vector<std::uint64_t> cell(n);
  for (std::size_t i = 0; i < n; ++i) {
    std::uint64_t c[3];
    for (int a = 0; a < 3; ++a) {
      const double q = std::floor((cloud(static_cast<Eigen::Index>(i), a) - lo(a)) / p.leaf);
      c[a] = std::min(static_cast<std::uint64_t>(std::max(q, 0.0)), dims(a) - 1);
    }
    cell[i] = c[0] + dims(0) * (c[1] + dims(1) * c[2]);
  }
  // The points in order of their cell (ties by row): a counting sort over a dense grid
  // when it is small beside the cloud, else a comparison sort.
  std::vector<std::uint32_t> order(n);
  const double cells = static_cast<double>(dims(0)) * static_cast<double>(dims(1)) * static_cast<double>(dims(2));
  if (cells <= 4.0 * static_cast<double>(n) + 65536) {
    std::vector<std::uint32_t> start(static_cast<std::size_t>(cells) + 1, 0);
    for (std::size_t i = 0; i < n; ++i) ++start[cell[i] + 1];
    for (std::size_t c = 1; c < start.size(); ++c) start[c] += start[c - 1];
    for (std::size_t i = 0; i < n; ++i) order[start[cell[i]]++] = static_cast<std::uint32_t>(i);
  } else {
    for (std::size_t i = 0; i < n; ++i) order[i] = static_cast<std::uint32_t>(i);
    std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
      return cell[a] != cell[b] ? cell[a] < cell[b] : a < b;
    });
  }
  FilteredCloud f;
  std::vector<Eigen::RowVector3d> centroids;
  for (std::size_t b = 0; b < n;) {
    std::size_t e = b;
    Eigen::RowVector3d sum = Eigen::RowVector3d::Zero();
    for (; e < n && cell[order[e]] == cell[order[b]]; ++e) sum += cloud.row(order[e]);
    const Eigen::RowVector3d centroid = sum / static_cast<double>(e - b);
    // The voxel's own point nearest its centroid (the first of equals).
    std::uint32_t best = order[b];
    double best_d2 = std::numeric_limits<double>::infinity();
    for (std::size_t k = b; k < e; ++k) {
      const double d2 = (cloud.row(order[k]) - centroid).squaredNorm();
      if (d2 < best_d2) best_d2 = d2, best = order[k];
    }
    centroids.push_back(centroid);
    f.source.push_back(best);
    b = e;
  }
  f.points.resize(static_cast<Eigen::Index>(centroids.size()), 3);
  for (std::size_t k = 0; k < centroids.size(); ++k) f.points.row(static_cast<Eigen::Index>(k)) = centroids[k];
  f.notes = std::to_string(cloud.rows()) + " points to " + std::to_string(centroids.size()) + " voxels";
  return f;
}

FilteredCloud region_growing_segmentation(const PointCloud& cloud, const RegionGrowingParams& p) {
  const char* who = "region_growing";
  require_points(cloud, 4, who);
  check_range(p.normal_k, 3, 500, who, "normal_k");
  check_range(p.neighbours, 3, 500, who, "neighbours");
  check_range(p.smoothness_deg, 0.1, 90, who, "smoothness_deg", " deg");
  check_range(p.curvature, 0, 1, who, "curvature");
  check_range(p.min_region, 1, 1e6, who, "min_region");
  check_range(p.plane_rms, 1e-5, 0.1, who, "plane_rms", " m");
  check_range(p.min_background_extent, 1e-3, 10, who, "min_background_extent", " m");
  check_range(p.cluster_tolerance, 0, 1, who, "cluster_tolerance", " m");
  Eigen::RowVector3d centre;
  const auto in = to_pcl(cloud, centre);
  auto tree = pcl::make_shared<pcl::search::KdTree<pcl::PointXYZ>>();
  auto normals = pcl::make_shared<pcl::PointCloud<pcl::Normal>>();
  pcl::NormalEstimation<pcl::PointXYZ, pcl::Normal> ne;
  ne.setInputCloud(in);
  ne.setSearchMethod(tree);
  ne.setKSearch(std::min<int>(p.normal_k, static_cast<int>(cloud.rows()) - 1));
  ne.compute(*normals);
  pcl::RegionGrowing<pcl::PointXYZ, pcl::Normal> rg;
  rg.setMinClusterSize(p.min_region);
  rg.setMaxClusterSize(std::numeric_limits<int>::max());
  rg.setSearchMethod(tree);
  rg.setNumberOfNeighbours(std::min<int>(p.neighbours, static_cast<int>(cloud.rows()) - 1));
  rg.setInputCloud(in);
  rg.setInputNormals(normals);
  rg.setSmoothnessThreshold(static_cast<float>(p.smoothness_deg * M_PI / 180));
  rg.setCurvatureThreshold(static_cast<float>(p.curvature));
  std::vector<pcl::PointIndices> regions;
  rg.extract(regions);
  std::vector<char> background(static_cast<std::size_t>(cloud.rows()), 0);
  int removed_regions = 0;
  for (const auto& r : regions) {
    const std::vector<Eigen::Index> rows = to_rows(r.indices);
    const Spread s = spread(cloud, rows);
    if (s.plane_rms < p.plane_rms && s.extent(0) > p.min_background_extent) {
      ++removed_regions;
      for (auto i : rows) background[static_cast<std::size_t>(i)] = 1;
    }
  }
  std::vector<Eigen::Index> rest;
  for (Eigen::Index i = 0; i < cloud.rows(); ++i) {
    if (!background[static_cast<std::size_t>(i)]) rest.push_back(i);
  }
  std::ostringstream notes;
  notes << regions.size() << " regions, " << removed_regions << " flat background regions removed";
  if (p.cluster_tolerance > 0 && !rest.empty()) {
    auto rest_cloud = pcl::make_shared<Cloud>();
    for (auto i : rest) rest_cloud->push_back((*in)[static_cast<std::size_t>(i)]);
    pcl::EuclideanClusterExtraction<pcl::PointXYZ> ec;
    ec.setClusterTolerance(p.cluster_tolerance);
    ec.setMinClusterSize(1);
    ec.setMaxClusterSize(std::numeric_limits<int>::max());
    ec.setSearchMethod(pcl::make_shared<pcl::search::KdTree<pcl::PointXYZ>>());
    ec.setInputCloud(rest_cloud);
    std::vector<pcl::PointIndices> clusters;
    ec.extract(clusters);  // sorted by decreasing size
    if (!clusters.empty()) {
      std::vector<Eigen::Index> keep;
      for (auto i : clusters.front().indices) keep.push_back(rest[static_cast<std::size_t>(i)]);
      notes << "; kept the largest of " << clusters.size() << " clusters";
      rest = std::move(keep);
    }
  }
  return subset(cloud, std::move(rest), notes.str());
}

std::vector<std::vector<Eigen::Index>> euclidean_clusters(const PointCloud& cloud, const EuclideanClusterParams& p) {
  const char* who = "euclidean_clusters";
  require_points(cloud, 0, who);
  check_range(p.tolerance, 1e-4, 1, who, "tolerance", " m");
  check_range(p.min_points, 1, 1e8, who, "min_points");
  std::vector<std::vector<Eigen::Index>> out;
  if (cloud.rows() == 0) return out;
  Eigen::RowVector3d centre;
  const auto in = to_pcl(cloud, centre);
  pcl::EuclideanClusterExtraction<pcl::PointXYZ> ec;
  ec.setClusterTolerance(p.tolerance);
  ec.setMinClusterSize(p.min_points);
  ec.setMaxClusterSize(std::numeric_limits<int>::max());
  ec.setSearchMethod(pcl::make_shared<pcl::search::KdTree<pcl::PointXYZ>>());
  ec.setInputCloud(in);
  std::vector<pcl::PointIndices> clusters;
  ec.extract(clusters);
  for (const auto& c : clusters) {
    std::vector<Eigen::Index> rows(c.indices.begin(), c.indices.end());
    std::sort(rows.begin(), rows.end());
    out.push_back(std::move(rows));
  }
  std::stable_sort(out.begin(), out.end(), [](const auto& a, const auto& b) {
    return a.size() != b.size() ? a.size() > b.size() : a.front() < b.front();
  });
  return out;
}

FilteredCloud lccp_stalk_removal(const PointCloud& cloud, const LccpStalkParams& p) {
  const char* who = "lccp_stalk_removal";
  require_points(cloud, 4, who);
  check_range(p.voxel_resolution, 1e-4, 0.1, who, "voxel_resolution", " m");
  check_range(p.seed_resolution, 1e-3, 0.5, who, "seed_resolution", " m");
  if (!(p.seed_resolution > p.voxel_resolution)) throw InputError("lccp_stalk_removal: seed_resolution must exceed voxel_resolution");
  check_range(p.spatial_importance, 0, 100, who, "spatial_importance");
  check_range(p.normal_importance, 0, 100, who, "normal_importance");
  check_range(p.concavity_tolerance_deg, 0, 90, who, "concavity_tolerance_deg", " deg");
  check_range(p.min_segment_size, 0, 1000, who, "min_segment_size");
  check_range(p.max_stalk_diameter, 1e-3, 0.1, who, "max_stalk_diameter", " m");
  check_range(p.elongation, 1, 100, who, "elongation");
  check_range(p.end_band, 0, 0.2, who, "end_band", " m");
  check_range(p.max_stalk_segments, 1, 20, who, "max_stalk_segments");
  Eigen::RowVector3d centre;
  const auto in = to_pcl(cloud, centre);

  // Supervoxels, their adjacency, then LCCP's merge of convex-connected supervoxels.
  pcl::SupervoxelClustering<pcl::PointXYZ> sv(static_cast<float>(p.voxel_resolution), static_cast<float>(p.seed_resolution));
  sv.setUseSingleCameraTransform(false);
  sv.setInputCloud(in);
  sv.setColorImportance(0);
  sv.setSpatialImportance(static_cast<float>(p.spatial_importance));
  sv.setNormalImportance(static_cast<float>(p.normal_importance));
  std::map<std::uint32_t, pcl::Supervoxel<pcl::PointXYZ>::Ptr> supervoxels;
  sv.extract(supervoxels);
  if (supervoxels.empty()) throw InputError("lccp_stalk_removal: no supervoxels (cloud too sparse for voxel_resolution)");
  std::multimap<std::uint32_t, std::uint32_t> adjacency;
  sv.getSupervoxelAdjacency(adjacency);
  pcl::LCCPSegmentation<pcl::PointXYZ> lccp;
  lccp.setConcavityToleranceThreshold(static_cast<float>(p.concavity_tolerance_deg));
  lccp.setSanityCheck(p.sanity_check);
  lccp.setSmoothnessCheck(true, static_cast<float>(p.voxel_resolution), static_cast<float>(p.seed_resolution), 0.1f);
  lccp.setKFactor(0);
  lccp.setMinSegmentSize(static_cast<unsigned>(p.min_segment_size));
  lccp.setInputSupervoxels(supervoxels, adjacency);
  lccp.segment();
  const auto labelled = sv.getLabeledCloud();  // one label per input point (0: unlabelled)
  lccp.relabelCloud(*labelled);
  if (labelled->size() != in->size()) throw std::logic_error("lccp_stalk_removal: PCL returned a labelled cloud of another size");

  std::map<std::uint32_t, std::vector<Eigen::Index>> segments;
  for (std::size_t i = 0; i < labelled->size(); ++i) segments[(*labelled)[i].label].push_back(static_cast<Eigen::Index>(i));

  std::vector<char> removed(static_cast<std::size_t>(cloud.rows()), 0);
  const Spread whole = spread(cloud, [&] {
    std::vector<Eigen::Index> all(static_cast<std::size_t>(cloud.rows()));
    for (Eigen::Index i = 0; i < cloud.rows(); ++i) all[static_cast<std::size_t>(i)] = i;
    return all;
  }());
  const Vec3 axis = whole.axis;
  int removed_segments = 0;
  std::size_t removed_points = 0;
  std::vector<Eigen::Index> stalk;  // rows removed so far
  const double touch2 = std::pow(2 * p.voxel_resolution, 2);
  auto touches_stalk = [&](const std::vector<Eigen::Index>& rows) {
    for (auto r : rows) {
      for (auto q : stalk) {
        if ((cloud.row(r) - cloud.row(q)).squaredNorm() <= touch2) return true;
      }
    }
    return false;
  };
  for (int round = 0; round < p.max_stalk_segments; ++round) {
    // Ends of what is left along the cloud's major axis.
    double lo = 1e300, hi = -1e300;
    for (Eigen::Index i = 0; i < cloud.rows(); ++i) {
      if (removed[static_cast<std::size_t>(i)]) continue;
      const double t = cloud.row(i).dot(axis);
      lo = std::min(lo, t);
      hi = std::max(hi, t);
    }
    // The first stalk segment is thin, elongated and reaches an end; the stalk then
    // continues through thin segments touching it (supervoxels cut a stalk into
    // pieces shorter than its elongation test).
    std::uint32_t best = 0;
    double best_reach = -1;
    for (const auto& [label, rows] : segments) {
      if (label == 0 || removed[static_cast<std::size_t>(rows.front())]) continue;
      if (stalk.empty() && rows.size() < 3) continue;
      const Spread s = spread(cloud, rows);
      if (!(s.extent(1) < p.max_stalk_diameter)) continue;
      if (stalk.empty()) {
        if (!(s.extent(0) > p.elongation * s.extent(1))) continue;
        double slo = 1e300, shi = -1e300;
        for (auto r : rows) {
          const double t = cloud.row(r).dot(axis);
          slo = std::min(slo, t);
          shi = std::max(shi, t);
        }
        if (!(shi >= hi - p.end_band || slo <= lo + p.end_band)) continue;
      } else if (s.extent(0) > p.max_stalk_diameter && !(s.extent(0) > p.elongation * s.extent(1))) {
        continue;  // a wide piece: not a stalk
      } else if (!touches_stalk(rows)) {
        continue;
      }
      if (s.extent(0) > best_reach) {
        best_reach = s.extent(0);
        best = label;
      }
    }
    if (best_reach < 0) break;
    for (auto r : segments[best]) {
      removed[static_cast<std::size_t>(r)] = 1;
      stalk.push_back(r);
    }
    removed_points += segments[best].size();
    ++removed_segments;
  }
  // Points no supervoxel took (label 0) go with the stalk when they touch it: left
  // behind, a few at the stalk's cut end would still set the height.
  if (!stalk.empty()) {
    const auto unlabelled = segments.find(0);
    const std::vector<Eigen::Index> loose = unlabelled == segments.end() ? std::vector<Eigen::Index>{} : unlabelled->second;
    for (bool grew = true; grew;) {
      grew = false;
      for (auto r : loose) {
        if (removed[static_cast<std::size_t>(r)] || !touches_stalk({r})) continue;
        removed[static_cast<std::size_t>(r)] = 1;
        stalk.push_back(r);
        ++removed_points;
        grew = true;
      }
    }
  }
  std::vector<Eigen::Index> keep;
  for (Eigen::Index i = 0; i < cloud.rows(); ++i) {
    if (!removed[static_cast<std::size_t>(i)]) keep.push_back(i);
  }
  std::ostringstream notes;
  notes << supervoxels.size() << " supervoxels, " << segments.size() << " LCCP segments, removed " << removed_segments
        << " stalk segments (" << removed_points << " points)";
  return subset(cloud, std::move(keep), notes.str());
}

const ParamTable<PassThroughParams>& pass_through_param_table() {
  using P = PassThroughParams;
  static const ParamTable<P> table =
      ParamTable<P>()
          .vec3("min", "m", &P::min, -1e9, 1e9, "box corner (seed 000 clipping, seed 003 Sect. 2.3)")
          .vec3("max", "m", &P::max, -1e9, 1e9, "opposite box corner")
          .validate([](const P& p, const ConfigNode& n) {
            for (int k = 0; k < 3; ++k) {
              if (!(p.min(k) < p.max(k))) n.fail("max", "must exceed `min` on every axis (x, y, z)");
            }
          });
  return table;
}

const ParamTable<EuclideanClusterParams>& euclidean_cluster_param_table() {
  using P = EuclideanClusterParams;
  static const ParamTable<P> table =
      ParamTable<P>()
          .real("tolerance", "m", &P::tolerance, 1e-4, 1, "gap between clusters (seed 003 Sect. II-B2: 0.01 m)")
          .integer("min_points", "count", &P::min_points, 1, 100000000, "smaller clusters are dropped (seed 003: 300)");
  return table;
}

const ParamTable<OutlierRemovalParams>& outlier_removal_param_table() {
  using P = OutlierRemovalParams;
  static const ParamTable<P> table =
      ParamTable<P>()
          .integer("mean_k", "count", &P::mean_k, 1, 1000, "n neighbours (seed 002 Sect. 2.1; PCL example value)")
          .real("stddev_mul", "sd", &P::stddev_mul, 0, 100, "delta, standard deviations (seed 002 Sect. 2.1)");
  return table;
}

const ParamTable<VoxelGridParams>& voxel_grid_param_table() {
  static const ParamTable<VoxelGridParams> table = ParamTable<VoxelGridParams>().real(
      "leaf", "m", &VoxelGridParams::leaf, 1e-4, 1, "voxel edge (seed 000 gives no value)");
  return table;
}

const ParamTable<RegionGrowingParams>& region_growing_param_table() {
  using P = RegionGrowingParams;
  static const ParamTable<P> table =
      ParamTable<P>()
          .integer("normal_k", "count", &P::normal_k, 3, 500, "neighbours for normals")
          .integer("neighbours", "count", &P::neighbours, 3, 500, "region-growing neighbourhood")
          .real("smoothness_deg", "deg", &P::smoothness_deg, 0.1, 90, "normal angle threshold (PCL example)")
          .real("curvature", "-", &P::curvature, 0, 1, "curvature threshold for seeds (PCL example)")
          .integer("min_region", "count", &P::min_region, 1, 1000000, "smallest region")
          .real("plane_rms", "m", &P::plane_rms, 1e-5, 0.1, "flatter regions are background")
          .real("min_background_extent", "m", &P::min_background_extent, 1e-3, 10, "and larger than this across")
          .real("cluster_tolerance", "m", &P::cluster_tolerance, 0, 1,
                "Euclidean clustering of what is left, the largest kept (0 keeps all)");
  return table;
}

const ParamTable<LccpStalkParams>& lccp_stalk_param_table() {
  using P = LccpStalkParams;
  static const ParamTable<P> table =
      ParamTable<P>()
          .real("voxel_resolution", "m", &P::voxel_resolution, 1e-4, 0.1, "supervoxel voxel (seed 002 gives none)")
          .real("seed_resolution", "m", &P::seed_resolution, 1e-3, 0.5, "supervoxel seed spacing")
          .real("spatial_importance", "-", &P::spatial_importance, 0, 100, "supervoxel spatial weight")
          .real("normal_importance", "-", &P::normal_importance, 0, 100, "supervoxel normal weight")
          .real("concavity_tolerance_deg", "deg", &P::concavity_tolerance_deg, 0, 90,
                "Eq. 5 angle tolerance (LCCP default)")
          .boolean("sanity_check", &P::sanity_check, "Eq. 6 sanity criterion")
          .integer("min_segment_size", "count", &P::min_segment_size, 0, 1000,
                   "supervoxels merged into neighbours below this")
          .real("max_stalk_diameter", "m", &P::max_stalk_diameter, 1e-3, 0.1, "extent across a stalk segment")
          .real("elongation", "-", &P::elongation, 1, 100, "a stalk segment is this much longer than wide")
          .real("end_band", "m", &P::end_band, 0, 0.2, "a stalk segment reaches this close to the cloud's end")
          .integer("max_stalk_segments", "count", &P::max_stalk_segments, 1, 20, "most segments removed")
          .validate([](const P& p, const ConfigNode& n) {
            if (!(p.seed_resolution > p.voxel_resolution)) n.fail("seed_resolution", "must exceed voxel_resolution");
          });
  return table;
}

}  // namespace grapebench
