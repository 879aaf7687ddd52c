#include "bench/scene_file.h"

#include "sensors/stereo_rgb.h"

#include <algorithm>
#include <cctype>

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "bench/protocols/registry.h"
#include "synth/read_regular_file.h"
#include "synth/utf8.h"

namespace grapebench {

namespace {

// Values of one sweep axis: a list of numbers, or {from, to, step}.
std::vector<double> sweep_values(const ConfigNode& sweep, const std::string& key) {
  const YAML::Node v = sweep.yaml()[key];
  if (v.IsSequence()) return sweep.get_real_list_any(key, 1, 10000, -1e300, 1e300);
  if (v.IsMap()) {
    const ConfigNode r = sweep.child(key);
    const double from = r.get_real("from", 0, -1e300, 1e300), to = r.get_real("to", 0, -1e300, 1e300);
    if (!r.has("from") || !r.has("to") || !r.has("step")) r.fail("", "a range needs from, to and step");
    const double step = r.get_real("step", 1, 1e-300, 1e300);
    const double count = std::floor((to - from) / step + 1e-9) + 1;
    if (!(count >= 1 && count <= 10000)) r.fail("step", "gives " + std::to_string(count) + " values; allowed 1-10000");
    std::vector<double> out;
    for (int k = 0; k < static_cast<int>(count); ++k) out.push_back(from + k * step);
    return out;
  }
  sweep.fail(key, "expected a list of numbers or {from, to, step}");
}

namespace {

// Each estimator measures what the protocol gives (a cloud or a stereo pair), and the
// stereo_pair protocol needs a colour stereo sensor.
void check_protocol_inputs(const ConfigNode& root, const Scene& s) {
  const std::string wanted = s.protocol == "stereo_pair"      ? "stereo_pair"
                             : s.protocol == "classification" ? "labelled_cloud"
                             : s.protocol == "detection"      ? "image"
                                                              : "cloud";
  for (const auto& e : s.estimators) {
    if (e.input != wanted && e.input != "any") {
      auto a = [](const std::string& kind) { return (kind == "image" ? "an " : "a ") + kind; };
      root.fail("estimators", "'" + e.name + "' (type " + e.type + ") measures " + a(e.input) + ", and protocol " +
                                  s.protocol + " gives " + a(wanted));
    }
  }
  // A vine row is seed 004's scene, or a dataset's (`grapebench dataset` reads it whatever the protocol).
  if (s.protocol == "classification" && !s.vine_row)
    root.fail("protocol", "protocol classification needs a `vine_row:` section (seed 004's scene)");
  if (s.vine_row && s.protocol != "classification" && s.protocol != "detection" && !root.has("dataset"))
    root.fail("vine_row", "a `vine_row:` section goes with protocol classification (seed 004's scene) or detection, "
                          "or a `dataset:` section");
  if (s.protocol == "detection" && s.sensor && s.sensor->type() != "stereo_rgb")
    root.fail("protocol", "detection needs a colour camera (sensor type stereo_rgb), not " + s.sensor->type());
  if (s.protocol == "stereo_pair" && !s.estimators.empty() && s.sensor && s.sensor->type() == "stereo_rgb" &&
      !static_cast<const StereoRgb&>(*s.sensor).params().right_image)
    root.fail("sensor", "right_image: false leaves protocol stereo_pair's estimators without their pair");
  if (s.protocol == "stereo_pair" && s.sensor && s.sensor->type() != "stereo_rgb") {
    root.fail("protocol", "stereo_pair needs a colour stereo sensor (type stereo_rgb), not " + s.sensor->type());
  }
}

}  // namespace

Scene read_scene(const ConfigNode& root, const std::string& path) {
  Scene s;
  s.path = path;
  s.name = root.get_string("name", std::filesystem::path(path).stem().string());
  // The name is a folder under --out: a safe file name, never a path.
  const bool safe = !s.name.empty() && s.name.size() <= 100 && s.name.front() != '.' && s.name.front() != '-' &&
                    std::all_of(s.name.begin(), s.name.end(), [](char c) {
                      return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.';
                    });
  if (!safe) {
    std::string shown;  // control bytes written out (a NUL cut the message short)
    for (const char c : s.name) {
      char hex[8];
      std::snprintf(hex, sizeof hex, "\\x%02X", static_cast<unsigned char>(c));
      shown += static_cast<unsigned char>(c) < 0x20 || c == 0x7f ? std::string(hex) : std::string(1, c);
    }
    root.fail("name", "'" + escape_invalid_utf8(shown) + "' is not a safe folder name: 1-100 of A-Z a-z 0-9 _ - . not starting with . or -" +
                          (root.has("name") ? "" : " (the default is the file's name; set `name:`)"));
  }
  if (!root.has("seed")) root.fail("seed", "missing: every scene names its seed (an unsigned integer)");
  s.seed = root.get_seed("seed", 0);
  s.protocol = root.get_choice("protocol", s.protocol, protocol_registry().types());
  if (!root.has("bunches")) root.fail("bunches", "missing: a list of {preset, count, parameters...}");
  for (const auto& node : root.children("bunches")) {
    BunchGroup g;
    g.preset = node.get_choice("preset", "table-red", preset_names());
    g.count = static_cast<int>(node.get_int("count", 1, 1, 100000));
    g.params = preset(g.preset);
    read_bunch_params(node, g.params);
    s.groups.push_back(std::move(g));
  }
  if (s.groups.empty()) root.fail("bunches", "the list is empty");
  if (root.has("sensor")) s.sensor = make_sensor(root.child("sensor"));
  if (root.has("rig")) s.rig = make_rig(root.child("rig"));
  if (root.has("background")) s.background = read_background(root.child("background"));
  if (root.has("foliage")) s.foliage = read_foliage(root.child("foliage"));
  if (root.has("vine_row")) {
    s.vine_row.emplace();
    vine_row_param_table().read(root.child("vine_row"), *s.vine_row);
  }
  if (root.has("dataset")) dataset_param_table().read(root.child("dataset"), s.dataset);
  if (s.rig && !s.sensor) root.fail("rig", "a rig needs a `sensor:` section");
  s.pipeline = root.has("pipeline") ? read_pipeline(root.child("pipeline"), s.protocol) : pipeline_defaults(s.protocol);
  if (root.has("estimators")) s.estimators = read_estimators(root);
  if (!s.estimators.empty() && !s.rig) root.fail("estimators", "estimators need a `sensor:` and a `rig:` to scan with");
  if (root.has("sweep")) {
    const ConfigNode sweep = root.child("sweep");
    for (const auto& kv : sweep.yaml()) {
      const std::string key = kv.first.as<std::string>();
      const YAML::Node list = kv.second;
      bool named = list.IsSequence() && list.size() > 0;
      for (std::size_t i = 0; named && i < list.size(); ++i) {
        double ignored;
        named = list[i].IsScalar() && !YAML::convert<double>::decode(list[i], ignored);
      }
      if (named) {
        SweepAxis axis{key, {}, sweep.get_string_list(key, 1)};
        for (std::size_t i = 0; i < axis.names.size(); ++i) axis.values.push_back(static_cast<double>(i));
        s.sweep.push_back(std::move(axis));
      } else {
        s.sweep.push_back({key, sweep_values(sweep, key), {}});
      }
    }
    if (s.sweep.empty()) root.fail("sweep", "the mapping is empty");
  }
  root.report_unused();
  check_protocol_inputs(root, s);
  return s;
}

}  // namespace

std::string read_scene_text(const std::string& path) { return read_regular_file(path, kMaxSceneFileBytes); }

Scene load_scene(const std::string& path) { return parse_scene(read_scene_text(path), path); }

namespace {

// Points `root` at path (dotted, `name[i]` indexes a list, a list without an index
// means every element) and sets the value there.
void substitute(YAML::Node node, const std::string& path, const YAML::Node& value, const std::string& where) {
  const auto dot = path.find('.');
  std::string head = path.substr(0, dot);
  const std::string rest = dot == std::string::npos ? "" : path.substr(dot + 1);
  int index = -1;
  if (const auto br = head.find('['); br != std::string::npos && head.back() == ']') {
    // Digits only (issue 39: stoi read "-1" as -1, "every element", and "1x" as 1).
    const std::string digits = head.substr(br + 1, head.size() - br - 2);
    if (digits.empty() || digits.size() > 6 || digits.find_first_not_of("0123456789") != std::string::npos)
      throw InputError(where + ": sweep key '" + path + "': bad index in '" + head + "' (a list index, 0 to 999999)");
    index = std::stoi(digits);
    head = head.substr(0, br);
  }
  if (node.IsMap() && !node[head] && rest.empty() && index < 0) {
    node[head] = value;  // a key left at its default; an unknown key is reported by the parser
    return;
  }
  if (!node.IsMap() || !node[head]) {
    throw InputError(where + ": sweep key '" + path + "': the scene has no '" + head +
                     "' here; sweep a key the scene sets (write its nominal value in the scene)");
  }
  YAML::Node child = node[head];
  std::vector<YAML::Node> targets;
  if (child.IsSequence()) {
    if (index >= static_cast<int>(child.size())) {
      throw InputError(where + ": sweep key '" + path + "': index " + std::to_string(index) + " beyond the list of " +
                       std::to_string(child.size()));
    }
    if (index >= 0) {
      targets.push_back(child[static_cast<std::size_t>(index)]);
    } else {
      for (auto e : child) targets.push_back(e);
    }
  } else {
    if (index >= 0) throw InputError(where + ": sweep key '" + path + "': '" + head + "' is not a list");
    if (rest.empty()) {
      node[head] = value;
      return;
    }
    targets.push_back(child);
  }
  if (rest.empty()) throw InputError(where + ": sweep key '" + path + "': names a list, not a number");
  for (auto& t : targets) substitute(t, rest, value, where);
}

std::string number_label(double v) {
  std::ostringstream s;
  s.precision(10);
  s << v;
  return s.str();
}

YAML::Node parse_yaml(const std::string& text, const std::string& name) { return ConfigNode::parse_strict(text, name); }

// The keys a document's sweep varies, as written ("sensor.renderer").
std::set<std::string> swept_keys(const YAML::Node& root) {
  std::set<std::string> out;
  if (root.IsMap() && root["sweep"] && root["sweep"].IsMap())
    for (const auto& kv : root["sweep"])
      if (kv.first.IsScalar()) out.insert(kv.first.Scalar());
  return out;
}

// The scene text with the lines of its top-level `sweep:` block blanked (line
// numbers elsewhere kept), or "" when the block does not stand on lines of its own.
std::string text_without_sweep(const std::string& text, const YAML::Node& root) {
  if (!root.IsMap() || root.Mark().line < 0) return "";
  int start = -1, end = -1;
  for (const auto& kv : root) {
    if (kv.first.as<std::string>() == "sweep") start = kv.first.Mark().line;
  }
  for (const auto& kv : root) {
    const int line = kv.first.Mark().line;
    if (line == start && kv.first.as<std::string>() != "sweep") return "";  // flow style: keys share the line
    if (line > start && (end < 0 || line < end)) end = line;
  }
  if (start < 0) return "";
  std::string out;
  int line = 0;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const bool blank = line >= start && (end < 0 || line < end);
    if (text[i] == '\n') {
      ++line;
      out += '\n';
    } else if (!blank) {
      out += text[i];
    }
  }
  return out;
}

// Expands the sweep. Each condition parses the scene anew (YAML::Clone would drop
// the line marks that errors name), without the sweep block when it can be cut out:
// parsing a long value list per condition made expansion quadratic. Values are taken
// from a document's own nodes (a node of another document would merge that
// document's node memory into this one: cubic). A condition that fails is redone
// with its value node from the list, so the error names the line of the value.
SceneSet expand(const std::string& text, const std::string& name) {
  SceneSet set;
  const YAML::Node root_yaml = parse_yaml(text, name);
  const std::set<std::string> swept = swept_keys(root_yaml);
  // A key read only under some values of a swept key: left by the other cells, it must
  // be read by at least one (its range and spelling checked there).
  std::map<std::string, std::string> skipped;
  std::set<std::string> read_somewhere;
  const auto gather = [&](const ConfigNode& cfg) {
    skipped.insert(cfg.skipped_keys().begin(), cfg.skipped_keys().end());
    read_somewhere.insert(cfg.conditional_keys_read().begin(), cfg.conditional_keys_read().end());
  };
  const ConfigNode base = ConfigNode::from_yaml(root_yaml, name, swept);
  set.base = read_scene(base, name);
  gather(base);
  // The expanded size, bounded before anything is expanded (issue 39): the sweep's
  // points times the bunches, each a case.
  std::size_t points = 1, bunches = 0;  // saturating: no product overflows
  for (const auto& a : set.base.sweep)
    points = std::min<std::size_t>(points * std::clamp<std::size_t>(a.values.size(), 1, 1000000), 1000000000000ull);
  for (const auto& g : set.base.groups) bunches = std::min<std::size_t>(bunches + static_cast<std::size_t>(g.count), 1000000000ull);
  constexpr std::size_t kMaxCases = 1000000;
  if (points <= 100000 && points * bunches > kMaxCases)
    throw InputError(name + ": the scene expands to " + std::to_string(points * bunches) + " cases (" +
                     std::to_string(points) + " sweep points x " + std::to_string(bunches) + " bunches); at most " +
                     std::to_string(kMaxCases));
  if (set.base.sweep.empty()) {
    set.conditions.push_back({{}, "", set.base});
    return set;
  }
  std::size_t total = 1;
  for (const auto& a : set.base.sweep) total *= a.values.size();
  if (total > 100000) throw InputError(name + ": the sweep has " + std::to_string(total) + " points; at most 100000");
  const std::string sweep_line = ConfigNode::from_yaml(root_yaml, name).where("sweep");
  std::string cut = text_without_sweep(text, root_yaml);
  if (!cut.empty()) {
    const YAML::Node check = parse_yaml(cut, name);
    if (!check.IsMap() || check["sweep"] || check.size() + 1 != root_yaml.size()) cut.clear();
  }
  const auto condition = [&](std::size_t flat, bool precise) {
    Condition c;
    const bool whole = precise || cut.empty();
    YAML::Node doc = parse_yaml(whole ? text : cut, name);
    std::size_t rest = flat;
    std::vector<std::size_t> idx(set.base.sweep.size());
    for (std::size_t a = set.base.sweep.size(); a-- > 0;) {
      idx[a] = rest % set.base.sweep[a].values.size();
      rest /= set.base.sweep[a].values.size();
    }
    for (std::size_t a = 0; a < set.base.sweep.size(); ++a) {
      const auto& axis = set.base.sweep[a];
      const double v = axis.values[idx[a]];
      c.values.push_back(v);
      YAML::Node value = axis.names.empty() ? YAML::Node(v) : YAML::Node(axis.names[idx[a]]);
      if (whole) {
        const YAML::Node written = YAML::Node(doc)["sweep"][axis.key];
        if (written.IsSequence()) value = written[idx[a]];  // keeps its line for errors
      }
      substitute(doc, axis.key, value, sweep_line);
      const auto dot = axis.key.rfind('.');
      c.label += (c.label.empty() ? "" : " ") + axis.key.substr(dot == std::string::npos ? 0 : dot + 1) + "=" +
                 (axis.names.empty() ? number_label(v) : axis.names[idx[a]]);
    }
    doc.remove("sweep");
    try {
      const ConfigNode cfg = ConfigNode::from_yaml(doc, name, swept);
      c.scene = read_scene(cfg, name);
      gather(cfg);
    } catch (const InputError& e) {
      throw InputError(std::string(e.what()) + " (sweep point " + c.label + ")");
    }
    c.scene.sweep = set.base.sweep;
    return c;
  };
  for (std::size_t flat = 0; flat < total; ++flat) {
    try {
      set.conditions.push_back(condition(flat, false));
    } catch (const InputError&) {
      set.conditions.push_back(condition(flat, true));  // throws again, naming the value's line
    }
  }
  for (const auto& [path, message] : skipped)
    if (!read_somewhere.count(path)) throw InputError(message + "; no value of the sweep selects it");
  return set;
}

}  // namespace

SceneSet parse_scene_set(const std::string& text, const std::string& name) { return expand(text, name); }

SceneSet load_scene_set(const std::string& path) { return parse_scene_set(read_scene_text(path), path); }

// The scene at its written (nominal) values. A key its sweep's cells read and these
// values do not is left here, as the cells that exclude it leave it; the sweep is
// expanded to check that some cell reads it.
Scene parse_scene(const std::string& text, const std::string& name) {
  const YAML::Node root = parse_yaml(text, name);
  const ConfigNode cfg = ConfigNode::from_yaml(root, name, swept_keys(root));
  Scene s = read_scene(cfg, name);
  if (!cfg.skipped_keys().empty()) expand(text, name);
  return s;
}

}  // namespace grapebench
