#include "algorithms/registry.h"

#include "algorithms/alpha_shape_volume.h"
#include "algorithms/convex_hull_volume.h"
#include "algorithms/cylinder_fit.h"
#include "algorithms/ellipsoid_fit.h"
#include "algorithms/percentile_box.h"
#include "algorithms/cylinder_model_volume.h"
#include "algorithms/external_estimator.h"
#include "algorithms/pca_box.h"
#include "algorithms/poisson_volume.h"
#include "algorithms/mls_smooth.h"
#include "algorithms/section_perimeters.h"
#include "algorithms/voxel_volume.h"

#include <algorithm>
#include <filesystem>

namespace grapebench {

const char* quantity_name(Quantity q) {
  switch (q) {
    case Quantity::Volume: return "volume";
    case Quantity::Height: return "height";
    case Quantity::Length: return "length";
    case Quantity::Width: return "width";
    case Quantity::PerimeterH: return "perimeter_h";
    case Quantity::PerimeterL: return "perimeter_l";
    case Quantity::PerimeterW: return "perimeter_w";
    case Quantity::SizeMajor: return "size_major";
    case Quantity::SizeMinor: return "size_minor";
  }
  return "?";
}

namespace {

Estimate size_pair(double a, double b) {
  return Estimate{{{Quantity::SizeMajor, std::max(a, b)}, {Quantity::SizeMinor, std::min(a, b)}}, false, {}};
}

PercentileBoxParams read_percentile_alpha(const ConfigNode& n, nlohmann::ordered_json& p) {
  PercentileBoxParams b;
  b.alpha = n.get_real("alpha", b.alpha, 0, 0.499);
  p["alpha"] = b.alpha;
  return b;
}

Estimate volume_only(const VolumeEstimate& v) {
  Estimate e;
  e.values = {{Quantity::Volume, v.volume}};
  e.watertight = v.watertight;
  e.notes = v.notes;
  return e;
}

// One line per estimator: type, summary, parameter reader.
const std::vector<EstimatorEntry> kEntries = {
    {"pca_box", "PCA-frame bounding box height/length/width (seed 000 Eq. 5, seed 002 Eqs. 7-9)",
     {Quantity::Height, Quantity::Length, Quantity::Width},
     [](const ConfigNode&, nlohmann::ordered_json&) -> BoundEstimator {
       return [](const PointCloud& c, const PointCloud&) {
         const PcaBox b = pca_box(c);
         return Estimate{{{Quantity::Height, b.height}, {Quantity::Length, b.length}, {Quantity::Width, b.width}}, false, {}};
       };
     }},
    {"section_perimeters", "perimeters of the three centre sections, Hobby spline, arc length (seed 002 Eqs. 10-12)",
     {Quantity::PerimeterH, Quantity::PerimeterL, Quantity::PerimeterW},
     [](const ConfigNode& n, nlohmann::ordered_json& p) -> BoundEstimator {
       SectionPerimeterParams s;
       s.half_width = n.get_real("half_width", s.half_width, 1e-4, 0.05);
       s.outline = n.get_choice("outline", s.outline, {"convex_hull", "angular"});
       s.angular_bins = static_cast<int>(n.get_int("angular_bins", s.angular_bins, 8, 3600));
       s.tension = n.get_real("tension", s.tension, 0.75, 4);
       p["half_width"] = s.half_width;
       p["outline"] = s.outline;
       p["angular_bins"] = s.angular_bins;
       p["tension"] = s.tension;
       return [s](const PointCloud& c, const PointCloud&) {
         const SectionPerimeters r = section_perimeters(c, s);
         Estimate e;
         e.values = {{Quantity::PerimeterH, r.perimeter(0)}, {Quantity::PerimeterL, r.perimeter(1)}, {Quantity::PerimeterW, r.perimeter(2)}};
         e.notes = "knots " + std::to_string(r.knots[0]) + "/" + std::to_string(r.knots[1]) + "/" + std::to_string(r.knots[2]);
         return e;
       };
     }},
    {"cylinder_model", "GM: cylinder of diameter max(l, w) and height h (seed 000 Eq. 6)",
     {Quantity::Volume},
     [](const ConfigNode&, nlohmann::ordered_json&) -> BoundEstimator {
       return [](const PointCloud& c, const PointCloud&) { return volume_only(cylinder_model_volume(c)); };
     }},
    {"convex_hull", "CH: convex hull volume (seed 000; CGAL quickhull)",
     {Quantity::Volume},
     [](const ConfigNode&, nlohmann::ordered_json&) -> BoundEstimator {
       return [](const PointCloud& c, const PointCloud&) { return volume_only(convex_hull_volume(c)); };
     }},
    {"alpha_shape", "AS: solid alpha complex volume (seed 000; CGAL), alpha as a radius in m",
     {Quantity::Volume},
     [](const ConfigNode& n, nlohmann::ordered_json& p) -> BoundEstimator {
       AlphaShapeParams a;
       a.alpha = n.get_real("alpha", a.alpha, 1e-4, 10);
       p["alpha"] = a.alpha;
       return [a](const PointCloud& c, const PointCloud&) { return volume_only(alpha_shape_volume(c, a)); };
     }},
    {"voxel", "VB: voxel counting (seed 000 Eq. 7), voxel edge in m",
     {Quantity::Volume},
     [](const ConfigNode& n, nlohmann::ordered_json& p) -> BoundEstimator {
       VoxelVolumeParams v;
       v.voxel_size = n.get_real("voxel_size", v.voxel_size, 1e-4, 0.5);
       v.fill_interior = n.get_bool("fill_interior", v.fill_interior);
       v.max_cells = n.get_real("max_cells", v.max_cells, 1e3, 1e9);
       p["voxel_size"] = v.voxel_size;
       p["fill_interior"] = v.fill_interior;
       p["max_cells"] = v.max_cells;
       return [v](const PointCloud& c, const PointCloud&) { return volume_only(voxel_volume(c, v)); };
     }},
    {"poisson", "PB: Poisson reconstruction from MLS normals, signed-tetrahedron volume (seed 000 Eq. 11; PCL, CGAL with solver: cgal, or screened Poisson with solver: screened)",
     {Quantity::Volume},
     [](const ConfigNode& n, nlohmann::ordered_json& p) -> BoundEstimator {
       PoissonParams q;
       const std::string solver = n.get_choice("solver", "pcl", {"pcl", "cgal", "screened"});
       q.solver = solver == "cgal" ? PoissonSolver::Cgal : solver == "screened" ? PoissonSolver::Screened : PoissonSolver::Pcl;
       p["solver"] = solver;
       if (q.solver == PoissonSolver::Pcl) {
         q.depth = static_cast<int>(n.get_int("depth", q.depth, 4, 12));
         q.samples_per_node = n.get_real("samples_per_node", q.samples_per_node, 1, 20);
         q.scale = n.get_real("scale", q.scale, 1, 2);
         p["depth"] = q.depth;
         p["samples_per_node"] = q.samples_per_node;
         p["scale"] = q.scale;
       } else if (q.solver == PoissonSolver::Screened) {
         q.screened.step = n.get_real("step", q.screened.step, 2e-4, 0.05);
         q.screened.screening = n.get_real("screening", q.screened.screening, 0, 1e4);
         q.screened.tolerance = n.get_real("tolerance", q.screened.tolerance, 1e-6, 0.1);
         q.area_neighbours = static_cast<int>(n.get_int("area_neighbours", q.area_neighbours, 2, 100));
         q.curved = n.get_bool("curved", q.curved);
         p["step"] = q.screened.step;
         p["screening"] = q.screened.screening;
         p["tolerance"] = q.screened.tolerance;
         p["area_neighbours"] = q.area_neighbours;
         p["curved"] = q.curved;
       } else {
         q.cell = n.get_real("cell", q.cell, 0, 0.05);
         q.step = n.get_real("step", q.step, 2e-4, 0.05);
         p["cell"] = q.cell;
         p["step"] = q.step;
       }
       q.mls.radius = n.get_real("mls_radius", q.mls.radius, 1e-4, 0.5);
       q.mls.polynomial_order = static_cast<int>(n.get_int("mls_order", q.mls.polynomial_order, 0, 4));
       p["mls_radius"] = q.mls.radius;
       p["mls_order"] = q.mls.polynomial_order;
       q.mls_positions = n.get_bool("mls_positions", q.mls_positions);
       p["mls_positions"] = q.mls_positions;
       // centroid: seed 000's sign rule (mls_smooth); facing: each normal turned toward
       // the camera that saw its point (PCL's flipNormalTowardsViewpoint).
       const bool facing = n.get_choice("orient", "centroid", {"centroid", "facing"}) == "facing";
       p["orient"] = facing ? "facing" : "centroid";
       return [q, facing](const PointCloud& c, const PointCloud& viewpoints) {
         if (!facing) return volume_only(poisson_volume(c, q));
         if (viewpoints.rows() != c.rows()) {
           throw InputError("poisson: orient: facing needs the camera of every point, and this pipeline gives " +
                            std::to_string(viewpoints.rows()) + " for " + std::to_string(c.rows()) + " points");
         }
         return volume_only(poisson_volume(c, q, viewpoints - c));
       };
     }},
    {"percentile_box_edges", "G_E: two largest edges of the percentile box, and its volume (seed 003 Alg. 1)",
     {Quantity::SizeMajor, Quantity::SizeMinor, Quantity::Volume},
     [](const ConfigNode& n, nlohmann::ordered_json& p) -> BoundEstimator {
       const PercentileBoxParams b = read_percentile_alpha(n, p);
       return [b](const PointCloud& c, const PointCloud&) {
         const PercentileBox box = percentile_box(c, b);
         Estimate e = size_pair(box.edges[0], box.edges[1]);
         e.values.push_back({Quantity::Volume, box.volume()});
         return e;
       };
     }},
    {"percentile_box_diagonals", "G_D: two largest face diagonals of the percentile box (seed 003 Alg. 1)",
     {Quantity::SizeMajor, Quantity::SizeMinor},
     [](const ConfigNode& n, nlohmann::ordered_json& p) -> BoundEstimator {
       const PercentileBoxParams b = read_percentile_alpha(n, p);
       return [b](const PointCloud& c, const PointCloud&) {
         const PercentileBox box = percentile_box(c, b);
         return size_pair(box.diagonals[0], box.diagonals[1]);
       };
     }},
    {"ellipsoid_fit", "G_R: two largest radii of the algebraic ellipsoid fit (seed 003, Petrov's fit)",
     {Quantity::SizeMajor, Quantity::SizeMinor},
     [](const ConfigNode& n, nlohmann::ordered_json& p) -> BoundEstimator {
       // Seed 003 compares the radii themselves with the cluster's length and width;
       // `diameters` doubles them (the like-for-like reading).
       const std::string measure = n.get_choice("measure", "radii", {"radii", "diameters"});
       p["measure"] = measure;
       const double k = measure == "radii" ? 1.0 : 2.0;
       return [k](const PointCloud& c, const PointCloud&) {
         const EllipsoidFit f = ellipsoid_fit(c);
         return size_pair(k * f.radii[0], k * f.radii[1]);
       };
     }},
    {"cylinder_fit", "G_C: diameter and height of the MSAC cylinder fit (seed 003, pcfitcylinder)",
     {Quantity::SizeMajor, Quantity::SizeMinor},
     [](const ConfigNode& n, nlohmann::ordered_json& p) -> BoundEstimator {
       CylinderFitParams f;
       f.max_distance = n.get_real("max_distance", f.max_distance, 1e-4, 0.5);
       f.min_radius = n.get_real("min_radius", f.min_radius, 1e-3, 1);
       f.max_radius = n.get_real("max_radius", f.max_radius, 1e-3, 1);
       f.max_iterations = static_cast<int>(n.get_int("max_iterations", f.max_iterations, 1, 1000000));
       f.normal_weight = n.get_real("normal_weight", f.normal_weight, 0, 1);
       f.normal_k = static_cast<int>(n.get_int("normal_k", f.normal_k, 3, 500));
       if (f.min_radius >= f.max_radius) n.fail("min_radius", "must be below max_radius");
       p["max_distance"] = f.max_distance;
       p["min_radius"] = f.min_radius;
       p["max_radius"] = f.max_radius;
       p["max_iterations"] = f.max_iterations;
       p["normal_weight"] = f.normal_weight;
       p["normal_k"] = f.normal_k;
       return [f](const PointCloud& c, const PointCloud&) {
         const CylinderFit fit = cylinder_fit(c, f);
         return size_pair(fit.diameter, fit.height);
       };
     }},
    {"external", "an external program through the JSON protocol (algorithms/README.md); set `quantities`",
     {},  // the scene's `quantities` list; filled in by make_estimator
     [](const ConfigNode& n, nlohmann::ordered_json& p) -> BoundEstimator {
       ExternalParams x;
       if (!n.has("command")) n.fail("command", "missing: the program and its arguments, e.g. [python3, my.py]");
       x.command = n.get_string_list("command", 1);
       const std::string scene_dir = std::filesystem::path(n.file()).parent_path().string();
       for (auto& a : x.command) {
         for (auto at = a.find("{scene_dir}"); at != std::string::npos; at = a.find("{scene_dir}")) {
           a.replace(at, 11, scene_dir.empty() ? "." : scene_dir);
         }
       }
       x.quantities = external_quantities(n);
       x.timeout = n.get_real("timeout", x.timeout, 0.1, 86400);
       p["command"] = x.command;
       nlohmann::ordered_json q = nlohmann::ordered_json::array();
       for (Quantity k : x.quantities) q.push_back(quantity_name(k));
       p["quantities"] = q;
       p["timeout_s"] = x.timeout;
       return [x](const PointCloud& c, const PointCloud&) { return external_estimate(c, x); };
     }},
};

}  // namespace

std::vector<Quantity> external_quantities(const ConfigNode& n) {
  std::vector<Quantity> out;
  if (!n.has("quantities")) return {Quantity::Volume};
  for (const auto& name : n.get_string_list("quantities", 1)) {
    bool found = false;
    for (Quantity q : kAllQuantities) {
      if (name == quantity_name(q)) {
        if (std::find(out.begin(), out.end(), q) == out.end()) out.push_back(q);
        found = true;
      }
    }
    if (!found) n.fail("quantities", "unknown quantity '" + name + "'; allowed: volume, height, length, width, perimeter_h, perimeter_l, perimeter_w");
  }
  return out;
}

const std::vector<EstimatorEntry>& estimator_registry() { return kEntries; }

namespace {

Vec3 read_vec3(const ConfigNode& n, const std::string& key, const Vec3& fallback) {
  if (!n.has(key)) return fallback;
  const auto v = n.get_real_list(key, 3, -1e9, 1e9);
  return {v[0], v[1], v[2]};
}

// One line per pipeline step: type, summary, parameter reader.
const std::vector<FilterEntry> kFilters = {
    {"pass_through", "keep the points in an axis-aligned box, m (seed 000 clipping, seed 003 Sect. 2.3)",
     [](const ConfigNode& n, nlohmann::ordered_json& p) -> BoundFilter {
       PassThroughParams f;
       f.min = read_vec3(n, "min", f.min);
       f.max = read_vec3(n, "max", f.max);
       for (int k = 0; k < 3; ++k) {
         if (!(f.min(k) < f.max(k))) n.fail("max", "must exceed `min` on every axis (x, y, z)");
       }
       p["min"] = {f.min.x(), f.min.y(), f.min.z()};
       p["max"] = {f.max.x(), f.max.y(), f.max.z()};
       return [f](const PointCloud& c) { return pass_through(c, f); };
     }},
    {"statistical_outlier", "statistical outlier removal, n neighbours and delta sd (seed 002 Sect. 2.1; PCL)",
     [](const ConfigNode& n, nlohmann::ordered_json& p) -> BoundFilter {
       OutlierRemovalParams f;
       f.mean_k = static_cast<int>(n.get_int("mean_k", f.mean_k, 1, 1000));
       f.stddev_mul = n.get_real("stddev_mul", f.stddev_mul, 0, 100);
       p["mean_k"] = f.mean_k;
       p["stddev_mul"] = f.stddev_mul;
       return [f](const PointCloud& c) { return statistical_outlier_removal(c, f); };
     }},
    {"voxel_grid", "voxel-grid downsampling to voxel centroids, leaf in m (seed 000; PCL)",
     [](const ConfigNode& n, nlohmann::ordered_json& p) -> BoundFilter {
       VoxelGridParams f;
       f.leaf = n.get_real("leaf", f.leaf, 1e-4, 1);
       p["leaf"] = f.leaf;
       return [f](const PointCloud& c) { return voxel_grid(c, f); };
     }},
    {"region_growing", "region growing on normals/curvature; flat large regions are background (seed 000; PCL)",
     [](const ConfigNode& n, nlohmann::ordered_json& p) -> BoundFilter {
       RegionGrowingParams f;
       f.normal_k = static_cast<int>(n.get_int("normal_k", f.normal_k, 3, 500));
       f.neighbours = static_cast<int>(n.get_int("neighbours", f.neighbours, 3, 500));
       f.smoothness_deg = n.get_real("smoothness_deg", f.smoothness_deg, 0.1, 90);
       f.curvature = n.get_real("curvature", f.curvature, 0, 1);
       f.min_region = static_cast<int>(n.get_int("min_region", f.min_region, 1, 1000000));
       f.plane_rms = n.get_real("plane_rms", f.plane_rms, 1e-5, 0.1);
       f.min_background_extent = n.get_real("min_background_extent", f.min_background_extent, 1e-3, 10);
       f.cluster_tolerance = n.get_real("cluster_tolerance", f.cluster_tolerance, 0, 1);
       p["normal_k"] = f.normal_k;
       p["neighbours"] = f.neighbours;
       p["smoothness_deg"] = f.smoothness_deg;
       p["curvature"] = f.curvature;
       p["min_region"] = f.min_region;
       p["plane_rms"] = f.plane_rms;
       p["min_background_extent"] = f.min_background_extent;
       p["cluster_tolerance"] = f.cluster_tolerance;
       return [f](const PointCloud& c) { return region_growing_segmentation(c, f); };
     }},
    {"lccp_stalk_removal", "remove the stalk: supervoxels + LCCP, thin elongated end segments (seed 002 Eqs. 5-6; PCL)",
     [](const ConfigNode& n, nlohmann::ordered_json& p) -> BoundFilter {
       LccpStalkParams f;
       f.voxel_resolution = n.get_real("voxel_resolution", f.voxel_resolution, 1e-4, 0.1);
       f.seed_resolution = n.get_real("seed_resolution", f.seed_resolution, 1e-3, 0.5);
       if (!(f.seed_resolution > f.voxel_resolution)) n.fail("seed_resolution", "must exceed voxel_resolution");
       f.spatial_importance = n.get_real("spatial_importance", f.spatial_importance, 0, 100);
       f.normal_importance = n.get_real("normal_importance", f.normal_importance, 0, 100);
       f.concavity_tolerance_deg = n.get_real("concavity_tolerance_deg", f.concavity_tolerance_deg, 0, 90);
       f.sanity_check = n.get_bool("sanity_check", f.sanity_check);
       f.min_segment_size = static_cast<int>(n.get_int("min_segment_size", f.min_segment_size, 0, 1000));
       f.max_stalk_diameter = n.get_real("max_stalk_diameter", f.max_stalk_diameter, 1e-3, 0.1);
       f.elongation = n.get_real("elongation", f.elongation, 1, 100);
       f.end_band = n.get_real("end_band", f.end_band, 0, 0.2);
       f.max_stalk_segments = static_cast<int>(n.get_int("max_stalk_segments", f.max_stalk_segments, 1, 20));
       p["voxel_resolution"] = f.voxel_resolution;
       p["seed_resolution"] = f.seed_resolution;
       p["spatial_importance"] = f.spatial_importance;
       p["normal_importance"] = f.normal_importance;
       p["concavity_tolerance_deg"] = f.concavity_tolerance_deg;
       p["sanity_check"] = f.sanity_check;
       p["min_segment_size"] = f.min_segment_size;
       p["max_stalk_diameter"] = f.max_stalk_diameter;
       p["elongation"] = f.elongation;
       p["end_band"] = f.end_band;
       p["max_stalk_segments"] = f.max_stalk_segments;
       return [f](const PointCloud& c) { return lccp_stalk_removal(c, f); };
     }},
    {"mls", "moving least squares smoothing and resampling, radius in m (seed 000 Eqs. 3-4; PCL)",
     [](const ConfigNode& n, nlohmann::ordered_json& p) -> BoundFilter {
       MlsParams f;
       f.radius = n.get_real("radius", f.radius, 1e-4, 0.5);
       f.polynomial_order = static_cast<int>(n.get_int("polynomial_order", f.polynomial_order, 0, 4));
       p["radius"] = f.radius;
       p["polynomial_order"] = f.polynomial_order;
       return [f](const PointCloud& c) {
         SmoothedCloud s = mls_smooth(c, f);
         FilteredCloud out;
         out.points = std::move(s.points);
         out.source = std::move(s.source);
         out.notes = "smoothed " + std::to_string(out.points.rows()) + " of " + std::to_string(c.rows()) + " points";
         return out;
       };
     }},
};

}  // namespace

const std::vector<FilterEntry>& filter_registry() { return kFilters; }

std::vector<std::string> filter_types() {
  std::vector<std::string> t;
  for (const auto& e : kFilters) t.push_back(e.type);
  return t;
}

const FilterEntry& find_filter(const ConfigNode& node) {
  if (!node.has("type")) node.fail("type", "missing: one of the registered pipeline steps (grapebench run --help)");
  const std::string type = node.get_choice("type", "", filter_types());
  for (const auto& e : kFilters) {
    if (e.type == type) return e;
  }
  node.fail("type", "missing");
}

std::vector<std::string> estimator_types() {
  std::vector<std::string> t;
  for (const auto& e : kEntries) t.push_back(e.type);
  return t;
}

const EstimatorEntry& find_estimator(const ConfigNode& node) {
  if (!node.has("type")) node.fail("type", "missing: one of the registered estimators (grapebench run --help)");
  const std::string type = node.get_choice("type", "", estimator_types());
  for (const auto& e : kEntries) {
    if (e.type == type) return e;
  }
  node.fail("type", "missing");
}

}  // namespace grapebench
