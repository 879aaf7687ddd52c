// One registry mechanism for every pluggable kind (sensor, rig, registration
// method, pipeline step, estimator, protocol): scene files name an entry by
// `type`; each entry is a type name, a one-line summary, its key table (for
// --help and the tests) and a create function that reads its parameters. Adding
// one is its file pair, one line in the kind's registry list and one CMake
// line.
#pragma once

#include <functional>
#include <memory>
#include <stdexcept>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "synth/config.h"
#include "synth/param_table.h"

namespace grapebench {

template <class Product>
struct RegistryEntry {
  std::string type;
  std::string summary;  // one line: paper, equation, what it does
  std::function<std::vector<KeyInfo>()> keys;
  // Every key that applies at the defaults, with its default value typed (JSON), as
  // `create` writes them for an entry written with no keys (the Python docs' signatures).
  std::function<nlohmann::ordered_json()> defaults;
  // Reads the entry's keys from the scene mapping (the scene reader reports the
  // keys nobody read) and writes them, defaults filled, to `params` for the
  // manifest.
  std::function<Product(const ConfigNode& node, nlohmann::ordered_json& params)> create;
};

// An entry whose parameters are the struct P read by `table` from `defaults`;
// `build` makes the product from the values read (and may read the node for
// context, such as the scene file's folder).
template <class Product, class P, class Build>
RegistryEntry<Product> entry(std::string type, std::string summary, ParamTable<P> table, P defaults, Build build) {
  auto t = std::make_shared<const ParamTable<P>>(std::move(table));
  auto d = std::make_shared<const P>(std::move(defaults));
  RegistryEntry<Product> e;
  e.type = std::move(type);
  e.summary = std::move(summary);
  e.keys = [t, d] { return t->keys(*d); };
  e.defaults = [t, d] { return t->to_json(*d); };
  e.create = [t, d, build](const ConfigNode& node, nlohmann::ordered_json& params) -> Product {
    P p = *d;
    t->read(node, p);
    params = t->to_json(p);
    return build(p, node);
  };
  return e;
}

template <class Product>
class Registry {
 public:
  using Entry = RegistryEntry<Product>;
  // kind: what the entries are, for messages ("estimator", "sensor").
  Registry(std::string kind, std::vector<Entry> entries) : kind_(std::move(kind)), entries_(std::move(entries)) {}

  const std::vector<Entry>& entries() const { return entries_; }
  const std::string& kind() const { return kind_; }
  std::vector<std::string> types() const {
    std::vector<std::string> t;
    for (const auto& e : entries_) t.push_back(e.type);
    return t;
  }
  // The entry node["type"] names (or `fallback` when the key is absent and the
  // fallback is not empty); unknown types name file:line and the registered
  // ones.
  const Entry& find(const ConfigNode& node, const std::string& fallback = {}) const {
    if (!node.has("type") && fallback.empty()) {
      node.fail("type", "missing: one of the registered " + kind_ + "s: " + join(types()));
    }
    const std::string type = node.get_choice("type", fallback, types());
    for (const auto& e : entries_) {
      if (e.type == type) return e;
    }
    node.fail("type", "unknown " + kind_);
  }
  // Reads the node's type and parameters; params gets {"type": ...,
  // parameters...}.
  Product create(const ConfigNode& node, nlohmann::ordered_json& params, const std::string& fallback = {}) const {
    const Entry& e = find(node, fallback);
    nlohmann::ordered_json p;
    Product out = e.create(node, p);
    params = with_type(e.type, p);
    return out;
  }
  // The product of `type` with every parameter at its default (a type known in code);
  // `params`, when given, gets {type, parameters...}.
  Product make(const std::string& type, nlohmann::ordered_json* params = nullptr) const {
    for (const auto& e : entries_) {
      if (e.type != type) continue;
      nlohmann::ordered_json p;
      Product out = e.create(ConfigNode::load_string("{}", kind_ + " " + type), p);
      if (params) *params = with_type(type, p);
      return out;
    }
    throw std::logic_error("no " + kind_ + " '" + type + "' is registered");
  }
  // Every type with its summary and keys, for --help.
  std::string help(const std::string& indent = "  ") const {
    std::string s;
    for (const auto& e : entries_) {
      s += indent + e.type + ": " + e.summary + "\n";
      const auto k = e.keys();
      s += k.empty() ? indent + "    (no keys)\n" : render_keys(k, indent + "    ");
    }
    return s;
  }

 private:
  static std::string join(const std::vector<std::string>& v) {
    std::string s;
    for (const auto& x : v) s += (s.empty() ? "" : ", ") + x;
    return s;
  }
  std::string kind_;
  std::vector<Entry> entries_;
};

}  // namespace grapebench
