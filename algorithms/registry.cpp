#include "algorithms/registry.h"

#include "algorithms/alpha_shape_volume.h"
#include "algorithms/convex_hull_volume.h"
#include "algorithms/cylinder_model_volume.h"
#include "algorithms/external_estimator.h"
#include "algorithms/pca_box.h"
#include "algorithms/poisson_volume.h"
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
  }
  return "?";
}

namespace {

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
       return [](const PointCloud& c) {
         const PcaBox b = pca_box(c);
         return Estimate{{{Quantity::Height, b.height}, {Quantity::Length, b.length}, {Quantity::Width, b.width}}, false, {}};
       };
     }},
    {"cylinder_model", "GM: cylinder of diameter max(l, w) and height h (seed 000 Eq. 6)",
     {Quantity::Volume},
     [](const ConfigNode&, nlohmann::ordered_json&) -> BoundEstimator {
       return [](const PointCloud& c) { return volume_only(cylinder_model_volume(c)); };
     }},
    {"convex_hull", "CH: convex hull volume (seed 000; CGAL quickhull)",
     {Quantity::Volume},
     [](const ConfigNode&, nlohmann::ordered_json&) -> BoundEstimator {
       return [](const PointCloud& c) { return volume_only(convex_hull_volume(c)); };
     }},
    {"alpha_shape", "AS: solid alpha complex volume (seed 000; CGAL), alpha as a radius in m",
     {Quantity::Volume},
     [](const ConfigNode& n, nlohmann::ordered_json& p) -> BoundEstimator {
       AlphaShapeParams a;
       a.alpha = n.get_real("alpha", a.alpha, 1e-4, 10);
       p["alpha"] = a.alpha;
       return [a](const PointCloud& c) { return volume_only(alpha_shape_volume(c, a)); };
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
       return [v](const PointCloud& c) { return volume_only(voxel_volume(c, v)); };
     }},
    {"poisson", "PB: Poisson reconstruction from MLS normals, signed-tetrahedron volume (seed 000 Eq. 11; PCL)",
     {Quantity::Volume},
     [](const ConfigNode& n, nlohmann::ordered_json& p) -> BoundEstimator {
       PoissonParams q;
       q.depth = static_cast<int>(n.get_int("depth", q.depth, 4, 12));
       q.samples_per_node = n.get_real("samples_per_node", q.samples_per_node, 1, 20);
       q.scale = n.get_real("scale", q.scale, 1, 2);
       q.mls.radius = n.get_real("mls_radius", q.mls.radius, 1e-4, 0.5);
       q.mls.polynomial_order = static_cast<int>(n.get_int("mls_order", q.mls.polynomial_order, 0, 4));
       p["depth"] = q.depth;
       p["samples_per_node"] = q.samples_per_node;
       p["scale"] = q.scale;
       p["mls_radius"] = q.mls.radius;
       p["mls_order"] = q.mls.polynomial_order;
       return [q](const PointCloud& c) { return volume_only(poisson_volume(c, q)); };
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
       return [x](const PointCloud& c) { return external_estimate(c, x); };
     }},
};

}  // namespace

std::vector<Quantity> external_quantities(const ConfigNode& n) {
  std::vector<Quantity> out;
  if (!n.has("quantities")) return {Quantity::Volume};
  for (const auto& name : n.get_string_list("quantities", 1)) {
    bool found = false;
    for (Quantity q : {Quantity::Volume, Quantity::Height, Quantity::Length, Quantity::Width}) {
      if (name == quantity_name(q)) {
        if (std::find(out.begin(), out.end(), q) == out.end()) out.push_back(q);
        found = true;
      }
    }
    if (!found) n.fail("quantities", "unknown quantity '" + name + "'; allowed: volume, height, length, width");
  }
  return out;
}

const std::vector<EstimatorEntry>& estimator_registry() { return kEntries; }

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
