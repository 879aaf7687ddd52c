// Key tables: each parameter of a scene-settable struct written once, with
// unit, allowed range or choices and one line of doc (Mitsuba keeps its
// parameter table in the plugin; this one is executable). One table drives the
// strict reader (file:line, key, allowed range), the manifest echo (the same
// key names, so a manifest's parameters read back as a scene) and `--help`.
//
//   static const ParamTable<VoxelVolumeParams> t =
//   ParamTable<VoxelVolumeParams>()
//       .real("voxel_size", "m", &VoxelVolumeParams::voxel_size, 1e-4, 0.5,
//       "voxel edge (seed 000 Eq. 7)");
//
// A field is a member pointer or, for nested structs, an accessor such as
// [](auto& p) -> auto& { return p.mls.radius; }.
//
// A row may apply only under a condition on fields read before it (`when`): a
// key the condition excludes is an error naming the condition ("read only with
// solver: screened"), never silently ignored; under a sweep of the key the
// condition names ("key: ..."), the cells that exclude it leave it, and a sweep
// none of whose cells reads it is that error (bench/scene_file.cpp). Cross-field
// rules go in `validate`.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "synth/config.h"
#include "synth/types.h"

namespace grapebench {

// One key of a table as text: for `--help`, the manifest and the table walk in
// tests.
struct KeyInfo {
  std::string key;
  std::string unit;           // "m", "deg", "-", "count", ...
  std::string range;          // "[0.0001, 0.5]", "centroid | facing", "true | false"
  std::string default_value;  // as it would be written in a scene
  std::string doc;            // one line, with the paper's citation
  std::string when;           // "" or the condition under which the key is read
  bool default_in_range = true;
};

// Number as a scene file would write it (shortest round trip of a double).
std::string param_number(double v);
std::string param_number(float v);
// Renders rows as an aligned block, each key followed by its doc line.
std::string render_keys(const std::vector<KeyInfo>& keys, const std::string& indent);

// {"type": type, params...}: how an entry's parameters appear in manifests
// (readable back as the scene section that made it).
inline nlohmann::ordered_json with_type(const std::string& type, const nlohmann::ordered_json& params) {
  nlohmann::ordered_json j = {{"type", type}};
  for (const auto& [k, v] : params.items()) j[k] = v;
  return j;
}

template <class T>
class ParamTable {
 public:
  using Pred = std::function<bool(const T&)>;
  // The type of the field a member pointer or accessor (auto& v) -> auto&
  // names.
  template <class F>
  using Field = std::remove_cvref_t<std::invoke_result_t<F&, T&>>;

  template <class F>
  ParamTable& real(std::string key, std::string unit, F f, double lo, double hi, std::string doc) {
    Row r =
        row(std::move(key), std::move(unit), "[" + param_number(lo) + ", " + param_number(hi) + "]", std::move(doc));
    r.read = [f, lo, hi](const ConfigNode& n, const std::string& k, T& v) {
      std::invoke(f, v) = n.get_real(k, std::invoke(f, v), lo, hi);
    };
    r.get = [f](const T& v) { return nlohmann::ordered_json(std::invoke(f, v)); };
    r.text = [f](const T& v) { return param_number(std::invoke(f, v)); };
    r.in_range = [f, lo, hi](const T& v) {
      return std::isfinite(std::invoke(f, v)) && std::invoke(f, v) >= lo && std::invoke(f, v) <= hi;
    };
    return add(std::move(r));
  }

  template <class F>
  ParamTable& integer(std::string key, std::string unit, F f, std::int64_t lo, std::int64_t hi, std::string doc) {
    Row r = row(std::move(key), std::move(unit), "[" + std::to_string(lo) + ", " + std::to_string(hi) + "]",
                std::move(doc));
    r.read = [f, lo, hi](const ConfigNode& n, const std::string& k, T& v) {
      std::invoke(f, v) = static_cast<Field<F>>(n.get_int(k, static_cast<std::int64_t>(std::invoke(f, v)), lo, hi));
    };
    r.get = [f](const T& v) { return nlohmann::ordered_json(std::invoke(f, v)); };
    r.text = [f](const T& v) { return std::to_string(std::invoke(f, v)); };
    r.in_range = [f, lo, hi](const T& v) {
      return static_cast<std::int64_t>(std::invoke(f, v)) >= lo && static_cast<std::int64_t>(std::invoke(f, v)) <= hi;
    };
    return add(std::move(r));
  }

  template <class F>
  ParamTable& boolean(std::string key, F f, std::string doc) {
    Row r = row(std::move(key), "-", "true | false", std::move(doc));
    r.read = [f](const ConfigNode& n, const std::string& k, T& v) {
      std::invoke(f, v) = n.get_bool(k, std::invoke(f, v));
    };
    r.get = [f](const T& v) { return nlohmann::ordered_json(std::invoke(f, v)); };
    r.text = [f](const T& v) { return std::string(std::invoke(f, v) ? "true" : "false"); };
    return add(std::move(r));
  }

  template <class F>
  ParamTable& seed(std::string key, F f, std::string doc) {
    Row r = row(std::move(key), "-", "[0, 2^64 - 1]", std::move(doc));
    r.read = [f](const ConfigNode& n, const std::string& k, T& v) {
      std::invoke(f, v) = n.get_seed(k, std::invoke(f, v));
    };
    r.get = [f](const T& v) { return nlohmann::ordered_json(std::invoke(f, v)); };
    r.text = [f](const T& v) { return std::to_string(std::invoke(f, v)); };
    return add(std::move(r));
  }

  // An enum written as one of `names` (name, value) in the scene.
  template <class F, class E = Field<F>>
  ParamTable& choice(std::string key, F f, std::vector<std::pair<std::string, std::type_identity_t<E>>> names,
                     std::string doc) {
    auto list = std::make_shared<const std::vector<std::pair<std::string, E>>>(std::move(names));
    Row r = row(std::move(key), "-", join_names(*list), std::move(doc));
    r.read = [f, list](const ConfigNode& n, const std::string& k, T& v) {
      const std::string s = n.get_choice(k, name_of(*list, std::invoke(f, v)), names_only(*list));
      for (const auto& [name, value] : *list) {
        if (name == s) std::invoke(f, v) = value;
      }
    };
    r.get = [f, list](const T& v) { return nlohmann::ordered_json(name_of(*list, std::invoke(f, v))); };
    r.text = [f, list](const T& v) { return name_of(*list, std::invoke(f, v)); };
    r.in_range = [f, list](const T& v) { return !name_of(*list, std::invoke(f, v)).empty(); };
    return add(std::move(r));
  }

  // A list of enums (each one of `names`, no repeats), at least `min_count`.
  template <class F, class E = typename Field<F>::value_type>
  ParamTable& choice_list(std::string key, F f, std::vector<std::pair<std::string, std::type_identity_t<E>>> names,
                          std::size_t min_count, std::string doc) {
    auto list = std::make_shared<const std::vector<std::pair<std::string, E>>>(std::move(names));
    Row r = row(std::move(key), "-", "list of " + join_names(*list), std::move(doc));
    r.read = [f, list, min_count](const ConfigNode& n, const std::string& k, T& v) {
      std::vector<E> out;
      for (const auto& s : n.get_string_list(k, min_count)) {
        bool found = false;
        for (const auto& [name, value] : *list) {
          if (name != s) continue;
          found = true;
          if (std::find(out.begin(), out.end(), value) != out.end()) n.fail(k, "'" + s + "' is listed twice");
          out.push_back(value);
        }
        if (!found) n.fail(k, "unknown value '" + s + "'; allowed: " + join_names(*list, ", "));
      }
      std::invoke(f, v) = std::move(out);
    };
    r.get = [f, list](const T& v) {
      nlohmann::ordered_json a = nlohmann::ordered_json::array();
      for (const E& e : std::invoke(f, v)) a.push_back(name_of(*list, e));
      return a;
    };
    r.text = [this_get = r.get](const T& v) { return this_get(v).dump(); };
    return add(std::move(r));
  }

  template <class F>
  ParamTable& rgb(std::string key, F f, std::string doc) {
    Row r = row(std::move(key), "rgb", "[r, g, b] each in [0, 1]", std::move(doc));
    r.read = [f](const ConfigNode& n, const std::string& k, T& v) {
      std::invoke(f, v) = read_rgb(n, k, std::invoke(f, v));
    };
    r.get = [f](const T& v) {
      return nlohmann::ordered_json{std::invoke(f, v).r, std::invoke(f, v).g, std::invoke(f, v).b};
    };
    r.text = [f](const T& v) {
      const Rgb& c = std::invoke(f, v);
      return "[" + param_number(c.r) + ", " + param_number(c.g) + ", " + param_number(c.b) + "]";
    };
    r.in_range = [f](const T& v) {
      for (float c : {std::invoke(f, v).r, std::invoke(f, v).g, std::invoke(f, v).b}) {
        if (!(c >= 0 && c <= 1)) return false;
      }
      return true;
    };
    return add(std::move(r));
  }

  template <class F>
  ParamTable& vec3(std::string key, std::string unit, F f, double lo, double hi, std::string doc) {
    Row r = row(std::move(key), std::move(unit),
                "[x, y, z] each in [" + param_number(lo) + ", " + param_number(hi) + "]", std::move(doc));
    r.read = [f, lo, hi](const ConfigNode& n, const std::string& k, T& v) {
      const auto x = n.get_real_list(k, 3, lo, hi);
      std::invoke(f, v) = Vec3(x[0], x[1], x[2]);
    };
    r.get = [f](const T& v) {
      return nlohmann::ordered_json{std::invoke(f, v).x(), std::invoke(f, v).y(), std::invoke(f, v).z()};
    };
    r.text = [g = r.get](const T& v) { return g(v).dump(); };
    r.in_range = [f, lo, hi](const T& v) {
      return std::invoke(f, v).minCoeff() >= lo && std::invoke(f, v).maxCoeff() <= hi;
    };
    return add(std::move(r));
  }

  // A list of min_count..max_count numbers, each in [lo, hi].
  template <class F>
  ParamTable& reals(std::string key, std::string unit, F f, std::size_t min_count, std::size_t max_count, double lo,
                    double hi, std::string doc) {
    Row r = row(std::move(key), std::move(unit),
                std::to_string(min_count) + "-" + std::to_string(max_count) + " numbers in [" + param_number(lo) +
                    ", " + param_number(hi) + "]",
                std::move(doc));
    r.read = [f, lo, hi, min_count, max_count](const ConfigNode& n, const std::string& k, T& v) {
      std::invoke(f, v) = n.get_real_list_any(k, min_count, max_count, lo, hi);
    };
    r.get = [f](const T& v) { return nlohmann::ordered_json(std::invoke(f, v)); };
    r.text = [g = r.get](const T& v) { return g(v).dump(); };
    r.in_range = [f, lo, hi, min_count, max_count](const T& v) {
      if (std::invoke(f, v).size() < min_count || std::invoke(f, v).size() > max_count) return false;
      for (double x : std::invoke(f, v)) {
        if (!(x >= lo && x <= hi)) return false;
      }
      return true;
    };
    return add(std::move(r));
  }

  // A list of at least min_count free strings (a command line, say).
  template <class F>
  ParamTable& strings(std::string key, F f, std::size_t min_count, std::string doc) {
    Row r = row(std::move(key), "-", "list of at least " + std::to_string(min_count) + " strings", std::move(doc));
    r.read = [f, min_count](const ConfigNode& n, const std::string& k, T& v) {
      std::invoke(f, v) = n.get_string_list(k, min_count);
    };
    r.get = [f](const T& v) { return nlohmann::ordered_json(std::invoke(f, v)); };
    r.text = [g = r.get](const T& v) { return g(v).dump(); };
    r.in_range = [f, min_count](const T& v) { return std::invoke(f, v).size() >= min_count; };
    return add(std::move(r));
  }

  // One free string (a module's name, say); at least one character.
  template <class F>
  ParamTable& string(std::string key, F f, std::string doc) {
    Row r = row(std::move(key), "-", "a string", std::move(doc));
    r.read = [f](const ConfigNode& n, const std::string& k, T& v) {
      std::string s = n.get_string(k, std::invoke(f, v));
      if (s.empty()) n.fail(k, "must not be empty");
      std::invoke(f, v) = std::move(s);
    };
    r.get = [f](const T& v) { return nlohmann::ordered_json(std::invoke(f, v)); };
    r.text = [g = r.get](const T& v) { return g(v).dump(); };
    r.in_range = [f](const T& v) { return !std::invoke(f, v).empty(); };
    return add(std::move(r));
  }

  // A free mapping handed through as JSON (ConfigNode::get_json): keys that only the
  // receiver knows (a Python estimator's own parameters).
  template <class F>
  ParamTable& document(std::string key, F f, std::string doc) {
    Row r = row(std::move(key), "-", "a mapping", std::move(doc));
    r.read = [f](const ConfigNode& n, const std::string& k, T& v) { std::invoke(f, v) = n.get_json(k); };
    r.get = [f](const T& v) { return nlohmann::ordered_json(std::invoke(f, v)); };
    r.text = [g = r.get](const T& v) { return g(v).dump(); };
    return add(std::move(r));
  }

  // A nested mapping read by its own table (the ICP settings of a
  // registration...).
  template <class F, class S = Field<F>>
  ParamTable& section(std::string key, F f, const ParamTable<std::type_identity_t<S>>& table, std::string doc) {
    auto sub = std::make_shared<const ParamTable<S>>(table);
    Row r = row(std::move(key), "section", "mapping", std::move(doc));
    r.read = [f, sub](const ConfigNode& n, const std::string& k, T& v) { sub->read(n.child(k), std::invoke(f, v)); };
    r.get = [f, sub](const T& v) { return sub->to_json(std::invoke(f, v)); };
    r.text = [](const T&) { return std::string("{...}"); };
    r.in_range = [f, sub](const T& v) {
      for (const auto& k : sub->keys(std::invoke(f, v))) {
        if (!k.default_in_range) return false;
      }
      return true;
    };
    r.nested = [f, sub](const T& v) { return sub->keys(std::invoke(f, v)); };
    return add(std::move(r));
  }

  // Every row and rule of another struct's table, at this level, read into the field
  // f: a struct that extends another's parameters takes its keys without writing them
  // twice (luo2016_instances over luo2016_stereo's four sections).
  template <class F, class S = Field<F>>
  ParamTable& extend(F f, const ParamTable<std::type_identity_t<S>>& table) {
    for (const auto& sr : table.rows_) {
      Row r = row(sr.key, sr.unit, sr.range, sr.doc);
      r.when = sr.when;
      r.required = sr.required;
      r.read = [f, g = sr.read](const ConfigNode& n, const std::string& k, T& v) { g(n, k, std::invoke(f, v)); };
      r.get = [f, g = sr.get](const T& v) { return g(std::invoke(f, v)); };
      if (sr.text) r.text = [f, g = sr.text](const T& v) { return g(std::invoke(f, v)); };
      if (sr.in_range) r.in_range = [f, g = sr.in_range](const T& v) { return g(std::invoke(f, v)); };
      if (sr.nested) r.nested = [f, g = sr.nested](const T& v) { return g(std::invoke(f, v)); };
      if (sr.active) r.active = [f, g = sr.active](const T& v) { return g(std::invoke(f, v)); };
      add(std::move(r));
    }
    for (const auto& rule : table.rules_)
      rules_.push_back([f, rule](const T& v, const ConfigNode& n) { rule(std::invoke(f, v), n); });
    return *this;
  }

  // The last row applies only when `pred` holds for the values read before it;
  // `condition` says so in messages and help ("solver: screened").
  ParamTable& when(std::string condition, Pred pred) {
    rows_.back().when = std::move(condition);
    rows_.back().active = std::move(pred);
    return *this;
  }

  // The last row has no default: a scene must set it.
  ParamTable& required() {
    rows_.back().required = true;
    return *this;
  }

  // Cross-field rules, run after every key is read; they call node.fail(key,
  // ...).
  ParamTable& validate(std::function<void(const T&, const ConfigNode&)> rule) {
    rules_.push_back(std::move(rule));
    return *this;
  }

  // Reads every key present in `node` into v (absent keys keep v's values),
  // then the cross-field rules. Keys this table does not know are left for
  // report_unused.
  void read(const ConfigNode& node, T& v) const {
    std::set<std::string> active_keys;
    for (const Row& r : rows_) {
      if (r.active && !r.active(v)) continue;
      active_keys.insert(r.key);
      if (node.has(r.key)) {
        r.read(node, r.key, v);
        if (r.active) node.note_conditional_read(r.key);
      } else if (r.required) {
        node.fail(r.key, "missing: " + r.doc);
      }
    }
    for (const Row& r : rows_) {
      if (r.active && !r.active(v) && !active_keys.count(r.key) && node.has(r.key)) {
        // Under a sweep of the setting it depends on ("renderer: ray" and a sweep of
        // renderer), the cells of the other values leave it; those of this one read it
        // (and a sweep where none does fails: bench/scene_file.cpp).
        const std::size_t colon = r.when.find(':');
        const std::string on = colon == std::string::npos ? std::string() : r.when.substr(0, colon);
        if (!on.empty() && on.find(' ') == std::string::npos && node.swept(on)) {
          node.skip(r.key, "is read only with " + r.when);
          continue;
        }
        node.fail(r.key, "is read only with " + r.when + "; remove it or change that setting");
      }
    }
    for (const auto& rule : rules_) rule(v, node);
  }

  // Every key that applies to v, with its value: reads back through read() as
  // v.
  nlohmann::ordered_json to_json(const T& v) const {
    nlohmann::ordered_json j = nlohmann::ordered_json::object();
    for (const Row& r : rows_) {
      if (!r.active || r.active(v)) j[r.key] = r.get(v);
    }
    return j;
  }

  // Every row, its default taken from `defaults`; nested sections' keys follow
  // their section as "section.key".
  std::vector<KeyInfo> keys(const T& defaults) const {
    std::vector<KeyInfo> out;
    for (const Row& r : rows_) {
      if (r.required) {
        out.push_back({r.key, r.unit, r.range, "(required)", r.doc, r.when, true});
        continue;
      }
      out.push_back({r.key, r.unit, r.range, r.text(defaults), r.doc, r.when, !r.in_range || r.in_range(defaults)});
      if (r.nested) {
        for (KeyInfo k : r.nested(defaults)) {
          k.key = r.key + "." + k.key;
          out.push_back(std::move(k));
        }
      }
    }
    return out;
  }

  std::string help(const T& defaults, const std::string& indent = "    ") const {
    return render_keys(keys(defaults), indent);
  }

 private:
  template <class>
  friend class ParamTable;  // extend() reads another table's rows
  struct Row {
    std::string key, unit, range, doc, when;
    std::function<void(const ConfigNode&, const std::string&, T&)> read;
    std::function<nlohmann::ordered_json(const T&)> get;
    std::function<std::string(const T&)> text;
    std::function<bool(const T&)> in_range;  // empty: any value is in range
    std::function<std::vector<KeyInfo>(const T&)> nested;
    Pred active;  // empty: always read
    bool required = false;
  };

  static Row row(std::string key, std::string unit, std::string range, std::string doc) {
    Row r;
    r.key = std::move(key);
    r.unit = std::move(unit);
    r.range = std::move(range);
    r.doc = std::move(doc);
    return r;
  }
  ParamTable& add(Row r) {
    for (const Row& other : rows_) {
      // Two rows may share a key only when conditions keep them apart (checked
      // in read).
      if (other.key == r.key && !other.active) throw std::logic_error("key table: '" + r.key + "' twice");
    }
    rows_.push_back(std::move(r));
    return *this;
  }
  template <class E>
  static std::string name_of(const std::vector<std::pair<std::string, E>>& list, const E& e) {
    for (const auto& [name, value] : list) {
      if (value == e) return name;
    }
    return {};
  }
  template <class E>
  static std::vector<std::string> names_only(const std::vector<std::pair<std::string, E>>& list) {
    std::vector<std::string> out;
    for (const auto& p : list) out.push_back(p.first);
    return out;
  }
  template <class E>
  static std::string join_names(const std::vector<std::pair<std::string, E>>& list, const char* sep = " | ") {
    std::string s;
    for (const auto& p : list) s += (s.empty() ? "" : sep) + p.first;
    return s;
  }

  std::vector<Row> rows_;
  std::vector<std::function<void(const T&, const ConfigNode&)>> rules_;
};

}  // namespace grapebench
