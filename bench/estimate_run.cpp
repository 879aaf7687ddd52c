#include "bench/estimate_run.h"

#include "algorithms/registry.h"
#include "bench/case_result.h"
#include "bench/scene_file.h"
#include "bench/scoring/scalars.h"
#include "synth/config.h"

#include <cmath>
#include <cstdio>
#include <sstream>

namespace grapebench {

std::vector<EstimatorSpec> estimators_from_arguments(const std::vector<std::string>& arguments) {
  std::string yaml = "estimators:\n";
  if (arguments.empty()) {
    for (const auto& type : estimator_registry().types()) {
      if (type != "external" && type != "python") yaml += "  - {type: " + type + "}\n";
    }
  }
  for (const auto& a : arguments) {
    const bool mapping = !a.empty() && a.front() == '{';
    if (!mapping && a.find_first_of(":{}[],\n#") != std::string::npos) {
      throw InputError("--estimator '" + a + "': a type name or a mapping {type: ..., key: value}");
    }
    yaml += "  - " + (mapping ? a : "{type: " + a + "}") + "\n";
  }
  const ConfigNode root = ConfigNode::load_string(yaml, "--estimator");
  std::vector<EstimatorSpec> all = read_estimators(root), cloud;
  for (auto& e : all) {
    if (e.input == "cloud") {
      cloud.push_back(std::move(e));
    } else if (!arguments.empty()) {
      throw InputError("--estimator " + e.type + ": it measures a " + e.input + ", not a point cloud");
    }
  }
  return cloud;
}

std::vector<EstimatorSpec> estimators_from_scene(const std::string& path) {
  const ConfigNode root = ConfigNode::load_string(read_scene_text(path), path);
  if (!root.has("estimators")) throw InputError(path + ": no `estimators:` list to run");
  std::vector<EstimatorSpec> out = read_estimators(root);
  for (const auto& e : out) {
    if (e.input != "cloud") throw InputError(path + ": estimator " + e.name + " measures a " + e.input + ", not a point cloud");
  }
  return out;
}

nlohmann::ordered_json estimate_cloud(const CloudFile& cloud, const std::string& file,
                                      const std::vector<EstimatorSpec>& estimators, Verbosity verbosity) {
  Progress progress("estimator", static_cast<int>(estimators.size()), verbosity);
  EstimatorInput input;
  input.points = cloud.points;
  if (cloud.normals.rows() == cloud.points.rows()) input.normals = cloud.normals;
  input.colours = cloud.colours;
  nlohmann::ordered_json answer;
  answer["file"] = file;
  answer["format"] = cloud.format;
  answer["points"] = cloud.points.rows();
  answer["dropped_nan"] = cloud.dropped_nan;
  answer["has_normals"] = cloud.normals.rows() > 0;
  answer["has_colours"] = !cloud.colours.empty();
  nlohmann::ordered_json runs = nlohmann::ordered_json::array();
  for (const EstimatorSpec& spec : estimators) {
    const TimedEstimate t = run_estimator(spec, input);
    nlohmann::ordered_json r;
    r["name"] = spec.name;
    r["type"] = spec.type;
    std::string error = !t.error.empty() ? t.error : t.estimate.error;
    // A value no number holds is a failure, never an answer (issue 39: an infinite
    // hull volume was printed as ok).
    for (const auto& [q, v] : t.estimate.values)
      if (error.empty() && !std::isfinite(v)) error = std::string(quantity_name(q)) + " is not a finite number";
    r["ok"] = error.empty();
    r["error"] = error;
    r["seconds"] = t.seconds;
    r["peak_heap_mb"] = t.peak_heap_mb;
    nlohmann::ordered_json values = nlohmann::ordered_json::object();
    if (error.empty()) {
      for (const auto& [q, v] : t.estimate.values) {
        const std::string name = quantity_name(q);
        values[name] = {{"value", v * display_scale(name)}, {"unit", display_unit(name)}};
      }
    }
    r["values"] = values;
    nlohmann::ordered_json points = nlohmann::ordered_json::object();
    for (const auto& [name, p] : t.estimate.points) points[name] = {p.x(), p.y(), p.z()};
    r["points"] = points;
    r["notes"] = t.estimate.notes;
    r["parameters"] = spec.params;
    runs.push_back(r);
    progress.done(spec.name, !error.empty());
  }
  answer["estimators"] = runs;
  return answer;
}

std::string estimate_table(const nlohmann::ordered_json& a) {
  std::ostringstream s;
  char line[512];
  std::snprintf(line, sizeof line, "%s: %lld points (%s)%s\n", a["file"].get<std::string>().c_str(),
                a["points"].get<long long>(), a["format"].get<std::string>().c_str(),
                a["dropped_nan"].get<long long>() > 0
                    ? (", " + std::to_string(a["dropped_nan"].get<long long>()) + " NaN points left out").c_str()
                    : "");
  s << line;
  std::snprintf(line, sizeof line, "  %-24s %-14s %14s %-5s %10s  %s\n", "estimator", "quantity", "value", "unit",
                "time ms", "notes");
  s << line;
  for (const auto& r : a["estimators"]) {
    const std::string name = r["name"].get<std::string>();
    const std::string notes = r["ok"].get<bool>() ? r["notes"].get<std::string>() : "FAILED: " + r["error"].get<std::string>();
    const double ms = r["seconds"].get<double>() * 1e3;
    bool first = true;
    for (const auto& [q, v] : r["values"].items()) {
      std::snprintf(line, sizeof line, "  %-24s %-14s %14.3f %-5s %10.1f  %s\n", first ? name.c_str() : "", q.c_str(),
                    v["value"].get<double>(), v["unit"].get<std::string>().c_str(), ms, first ? notes.substr(0, 80).c_str() : "");
      s << line;
      first = false;
    }
    for (const auto& [p, xyz] : r["points"].items()) {
      std::snprintf(line, sizeof line, "  %-24s %-14s (%.4f, %.4f, %.4f) m\n", first ? name.c_str() : "", p.c_str(),
                    xyz[0].get<double>(), xyz[1].get<double>(), xyz[2].get<double>());
      s << line;
      first = false;
    }
    if (first) {
      std::snprintf(line, sizeof line, "  %-24s %-14s %14s %-5s %10.1f  %s\n", name.c_str(), "-", "-", "", ms, notes.substr(0, 120).c_str());
      s << line;
    }
  }
  return s.str();
}

}  // namespace grapebench
