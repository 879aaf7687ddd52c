#include "algorithms/segmentation/seed003_roi.h"

#include "synth/config.h"

#include <algorithm>
#include <sstream>

namespace grapebench {

namespace {

void check(const Seed003RoiParams& p) {
  const char* who = "seed003 roi";
  check_range(p.detection_clusters, 1, 64, who, "detection_clusters");
  check_range(p.separation_clusters, 1, 64, who, "separation_clusters");
  check_range(p.n_min, -1, 1, who, "n_min");
  check_range(p.d_min, -1, 1, who, "d_min");
  check_range(p.d_max, -1, 1, who, "d_max");
  check_range(p.i_min, -1, 1, who, "i_min");
  check_range(p.roi_radius, 0.01, 2, who, "roi_radius", " m");
}

bool grape_colour(const Vec3& centroid, const Seed003RoiParams& p) {
  if (p.rule == GrapeColourRule::Red) return centroid.x() > p.n_min && centroid.y() > p.d_min;
  return centroid.y() < p.d_max && centroid.z() > p.i_min;
}

PointCloud rows_of(const PointCloud& cloud, const Region& rows) {
  PointCloud out(static_cast<Eigen::Index>(rows.size()), 3);
  for (std::size_t i = 0; i < rows.size(); ++i) out.row(static_cast<Eigen::Index>(i)) = cloud.row(rows[i]);
  return out;
}

// NDI features of the given rows.
std::vector<Vec3> features_of(const std::vector<Rgb8>& rgb, const Region& rows) {
  std::vector<Vec3> f(rows.size());
  for (std::size_t i = 0; i < rows.size(); ++i) f[i] = ndi(rgb[static_cast<std::size_t>(rows[i])]);
  return f;
}

// The rows of `rows` whose k-means cluster passes the colour rule; appends to notes.
Region grape_coloured(const std::vector<Rgb8>& rgb, const Region& rows, const Seed003RoiParams& p,
                      std::uint64_t seed, std::ostringstream& notes) {
  Region out;
  if (rows.size() < static_cast<std::size_t>(p.separation_clusters)) return out;
  const KMeansResult km = kmeans_pp(features_of(rgb, rows), {p.separation_clusters, 100, seed});
  std::vector<char> grape(km.centroids.size());
  int chosen = 0;
  for (std::size_t c = 0; c < km.centroids.size(); ++c) {
    grape[c] = km.sizes[c] > 0 && grape_colour(km.centroids[c], p);
    chosen += grape[c];
  }
  notes << chosen << " of " << km.centroids.size() << " colour clusters grape-coloured";
  for (std::size_t i = 0; i < rows.size(); ++i) {
    if (grape[static_cast<std::size_t>(km.label[i])]) out.push_back(rows[i]);
  }
  return out;
}

void check_inputs(const PointCloud& cloud, const std::vector<Rgb8>& rgb, const char* who) {
  require_points(cloud, 0, who);
  if (static_cast<std::size_t>(cloud.rows()) != rgb.size()) {
    throw InputError(std::string(who) + ": " + std::to_string(cloud.rows()) + " points but " +
                     std::to_string(rgb.size()) + " colours");
  }
}

}  // namespace

Seed003Detection detect_grape_regions(const PointCloud& cloud, const std::vector<Rgb8>& rgb,
                                      const Seed003RoiParams& p) {
  check(p);
  check_inputs(cloud, rgb, "detect_grape_regions");
  Seed003Detection d;
  std::ostringstream notes;
  const auto n = static_cast<std::size_t>(cloud.rows());
  if (n < static_cast<std::size_t>(p.detection_clusters)) {
    d.notes = "too few points for the colour clustering";
    return d;
  }
  // Step 2: 5 NDI clusters, the one whose centroid has the largest N kept (grapes
  // and the foliage around them).
  const KMeansResult first = kmeans_pp(ndi(rgb), {p.detection_clusters, 100, p.seed});
  std::size_t best = 0;
  for (std::size_t c = 1; c < first.centroids.size(); ++c) {
    if (first.sizes[c] > 0 && (first.sizes[best] == 0 || first.centroids[c].x() > first.centroids[best].x())) best = c;
  }
  Region kept;
  for (std::size_t i = 0; i < n; ++i) {
    if (static_cast<std::size_t>(first.label[i]) == best) kept.push_back(static_cast<Eigen::Index>(i));
  }
  notes << "highest-N cluster " << kept.size() << " of " << n << " points (N = " << first.centroids[best].x()
        << "); ";
  // Step 3: grapes from foliage by a second NDI clustering and the colour rule.
  const Region grapes = grape_coloured(rgb, kept, p, p.seed + 1, notes);
  // Step 4: spatial clusters of at least min_points are the regions.
  if (!grapes.empty()) {
    for (const auto& c : euclidean_clusters(rows_of(cloud, grapes), p.clusters)) {
      Region r;
      for (auto i : c) r.push_back(grapes[static_cast<std::size_t>(i)]);
      d.regions.push_back(std::move(r));
    }
  }
  notes << "; " << d.regions.size() << " regions";
  d.notes = notes.str();
  return d;
}

Region roi_from_centre_of_mass(const PointCloud& cloud, const Region& rough, double radius) {
  check_range(radius, 0.01, 2, "roi_from_centre_of_mass", "radius", " m");
  Region out;
  if (rough.empty()) return out;
  Eigen::RowVector3d cm = Eigen::RowVector3d::Zero();
  for (auto i : rough) {
    if (i < 0 || i >= cloud.rows()) throw InputError("roi_from_centre_of_mass: row " + std::to_string(i) + " outside the cloud");
    cm += cloud.row(i);
  }
  cm /= static_cast<double>(rough.size());
  for (Eigen::Index i = 0; i < cloud.rows(); ++i) {
    const Eigen::RowVector3d d = (cloud.row(i) - cm).cwiseAbs();
    if (d.maxCoeff() < radius) out.push_back(i);
  }
  return out;
}

Region fine_tune_region(const PointCloud& cloud, const std::vector<Rgb8>& rgb, const Region& region,
                        const Seed003RoiParams& p) {
  check(p);
  check_inputs(cloud, rgb, "fine_tune_region");
  std::ostringstream notes;
  const Region grapes = grape_coloured(rgb, region, p, p.seed + 2, notes);
  if (grapes.empty()) return {};
  EuclideanClusterParams ec = p.clusters;
  ec.min_points = 1;
  const auto clusters = euclidean_clusters(rows_of(cloud, grapes), ec);
  Region out;
  for (auto i : clusters.front()) out.push_back(grapes[static_cast<std::size_t>(i)]);
  std::sort(out.begin(), out.end());
  return out;
}

const ParamTable<Seed003RoiParams>& seed003_roi_param_table() {
  using P = Seed003RoiParams;
  static const ParamTable<P> table =
      ParamTable<P>()
          .integer("detection_clusters", "count", &P::detection_clusters, 1, 64,
                   "k of the first NDI k-means (seed 003: 5, highest-N centroid kept)")
          .integer("separation_clusters", "count", &P::separation_clusters, 1, 64,
                   "k of the grape/foliage k-means (seed 003: 3)")
          .choice("rule", &P::rule, {{"red", GrapeColourRule::Red}, {"black", GrapeColourRule::Black}},
                  "grape centroid rule: red (N > n_min, D > d_min) or black (D < d_max, I > i_min), seed 003")
          .real("n_min", "-", &P::n_min, -1, 1, "red rule: centroid N above (seed 003: 0.2)")
          .real("d_min", "-", &P::d_min, -1, 1, "red rule: centroid D above (seed 003: 0.2)")
          .real("d_max", "-", &P::d_max, -1, 1, "black rule: centroid D below (seed 003: 0.2)")
          .real("i_min", "-", &P::i_min, -1, 1, "black rule: centroid I above (seed 003: -0.05)")
          .real("cluster_tolerance", "m", [](auto& p) -> auto& { return p.clusters.tolerance; }, 1e-4, 1,
                "Euclidean clustering gap (seed 003: 0.01 m)")
          .integer("cluster_min_points", "count", [](auto& p) -> auto& { return p.clusters.min_points; }, 1, 100000000,
                   "smaller clusters are dropped (seed 003: 300)")
          .real("radius", "m", &P::roi_radius, 0.01, 2, "R of Eq. 2, the ROI about the centre of mass (seed 003: 0.15)")
          .seed("kmeans_seed", &P::seed, "seed of the k-means++ draws");
  return table;
}

}  // namespace grapebench
