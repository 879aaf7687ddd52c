#include "synth/config.h"

#include "synth/utf8.h"

#include <yaml-cpp/eventhandler.h>
#include <yaml-cpp/parser.h>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <regex>
#include <fstream>
#include <optional>
#include <set>
#include <sstream>

namespace grapebench {

namespace {

std::string line_of(const YAML::Node& n) {
  const YAML::Mark m = n.Mark();
  return m.line >= 0 ? std::to_string(m.line + 1) : "?";
}

std::string fmt(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

}  // namespace

void check_range(double v, double lo, double hi, const char* who, const char* name, const char* unit) {
  if (!(v >= lo && v <= hi)) {
    std::ostringstream s;
    s << who << ": " << name << " = " << v << unit << " outside the allowed range [" << lo << ", " << hi << "]";
    throw InputError(s.str());
  }
}

ConfigNode::ConfigNode(YAML::Node node, std::shared_ptr<State> state, std::string path)
    : node_(std::move(node)),
      state_(std::move(state)),
      path_(std::move(path)),
      used_(std::make_shared<std::set<std::string>>()) {}

namespace {

// Strict YAML: what yaml-cpp accepts silently but a scene must not hold. Duplicate
// keys (yaml-cpp keeps both and lookups see the first), keys that are not plain
// scalars, and explicit tags (`!!str 5` would be read as the number 5 anyway).
void check_strict(const YAML::Node& node, const std::string& name, int depth) {
  const auto at = [&](const YAML::Node& n) { return name + ":" + std::to_string(n.Mark().line + 1) + ": "; };
  if (depth > 64) throw InputError(at(node) + "nested more than 64 levels deep");
  if (node.Tag() != "?" && node.Tag() != "!" && !node.Tag().empty()) {
    throw InputError(at(node) + "explicit YAML tag '" + node.Tag() + "' is not allowed; write the plain value");
  }
  if (node.IsMap()) {
    std::set<std::string> seen;
    for (const auto& kv : node) {
      if (!kv.first.IsScalar()) throw InputError(at(kv.first) + "a key must be a plain name, not a list or mapping");
      if (!seen.insert(kv.first.Scalar()).second) {
        throw InputError(at(kv.first) + "'" + kv.first.Scalar() + "' is given twice in the same mapping");
      }
      check_strict(kv.first, name, depth + 1);
      check_strict(kv.second, name, depth + 1);
    }
  } else if (node.IsSequence()) {
    for (const auto& item : node) check_strict(item, name, depth + 1);
  }
}

}  // namespace

namespace {

// Events of a document, ignored: only whether a second document exists matters, and
// where it starts.
class DocumentCounter : public YAML::EventHandler {
 public:
  int line = -1;  // 0-based line of the last document's start
  // Set: an alias is refused, naming this file. An alias is a reference, so a
  // kilobyte of nested ones stands for billions of nodes, which every walk of the
  // document (the strict-key check, a sweep's copy) would visit.
  std::optional<std::string> refuse_aliases;
  void OnDocumentStart(const YAML::Mark& m) override { line = m.line; }
  void OnDocumentEnd() override {}
  void OnNull(const YAML::Mark&, YAML::anchor_t) override {}
  void OnAlias(const YAML::Mark& m, YAML::anchor_t) override {
    if (refuse_aliases)
      throw InputError(*refuse_aliases + ":" + std::to_string(m.line + 1) +
                       ": a YAML alias (*name): not supported, write the value out (aliases can expand a small "
                       "file into billions of nodes)");
  }
  void OnScalar(const YAML::Mark&, const std::string&, YAML::anchor_t, const std::string&) override {}
  void OnSequenceStart(const YAML::Mark&, const std::string&, YAML::anchor_t, YAML::EmitterStyle::value) override {}
  void OnSequenceEnd() override {}
  void OnMapStart(const YAML::Mark&, const std::string&, YAML::anchor_t, YAML::EmitterStyle::value) override {}
  void OnMapEnd() override {}
};

}  // namespace

YAML::Node ConfigNode::parse_strict(const std::string& text, const std::string& name) {
  if (const std::size_t at = invalid_utf8_at(text); at != std::string::npos) {
    const auto line = 1 + std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(at), '\n');
    throw InputError(name + ":" + std::to_string(line) + ": not UTF-8 (byte " + std::to_string(at) + ", 0x" +
                     escape_invalid_utf8(text.substr(at, 1)).substr(2) + "): scene files are UTF-8 text");
  }
  YAML::Node root;
  try {
    // Not YAML::LoadAll: yaml-cpp 0.7 loops forever, allocating, on a stray ","
    // outside a flow collection (found by tests/fuzz/scene_fuzz.cpp). The first
    // document is read as events (aliases refused) and then loaded; the parser is
    // then asked for a second one, once.
    std::istringstream in(text);
    YAML::Parser parser(in);
    DocumentCounter counter;
    counter.refuse_aliases = name;
    parser.HandleNextDocument(counter);
    counter.refuse_aliases.reset();
    root = YAML::Load(text);
    if (parser.HandleNextDocument(counter)) {
      throw InputError(name + ":" + std::to_string(counter.line + 1) +
                       ": a second YAML document, or text after the first; a scene file holds one");
    }
  } catch (const YAML::Exception& e) {
    throw InputError(name + ":" + std::to_string(e.mark.line + 1) +
                     ": YAML syntax error: " + e.msg);
  }
  check_strict(root, name, 0);
  return root;
}

ConfigNode ConfigNode::load_string(const std::string& text, const std::string& name) {
  return from_yaml(parse_strict(text, name), name);
}

ConfigNode ConfigNode::from_yaml(YAML::Node root, const std::string& name, std::set<std::string> swept) {
  if (root.IsNull()) root = YAML::Node(YAML::NodeType::Map);
  auto state = std::make_shared<State>();
  state->file = name;
  state->swept = std::move(swept);
  ConfigNode cfg(root, state, "");
  if (!root.IsMap()) cfg.fail("", "the document must be a mapping of keys to values");
  return cfg;
}

std::string ConfigNode::full_path(const std::string& key) const {
  return path_.empty() ? key : path_ + "." + key;
}

bool ConfigNode::swept(const std::string& key) const {
  return state_->swept.count(full_path(key)) > 0;
}

void ConfigNode::skip(const std::string& key, const std::string& why) const {
  used_->insert(key);
  const std::string path = full_path(key);
  state_->skipped.emplace(path, where(key) + ": '" + path + "': " + why);
}

void ConfigNode::note_conditional_read(const std::string& key) const {
  state_->conditional_read.insert(full_path(key));
}

std::string ConfigNode::where(const std::string& key) const {
  if (!key.empty() && node_.IsMap() && node_[key]) {
    // The key's own line where the parser marked it (a nested mapping's value starts on
    // the next line); a key a sweep inserted has no mark, its value has.
    for (const auto& kv : node_) {
      if (kv.first.IsScalar() && kv.first.Scalar() == key && kv.first.Mark().line >= 0) {
        return state_->file + ":" + line_of(kv.first);
      }
    }
    return state_->file + ":" + line_of(node_[key]);
  }
  return state_->file + ":" + line_of(node_);
}

void ConfigNode::fail(const std::string& key, const std::string& message) const {
  const std::string name = key.empty() ? path_ : full_path(key);
  throw InputError(where(key) + ": " + (name.empty() ? "" : "'" + name + "': ") + message);
}

bool ConfigNode::has(const std::string& key) const {
  return node_.IsMap() && static_cast<bool>(node_[key]);
}

YAML::Node ConfigNode::value(const std::string& key) const {
  used_->insert(key);
  return node_[key];
}

double ConfigNode::get_real(const std::string& key, double fallback, double lo,
                            double hi) const {
  if (!has(key)) return fallback;
  const YAML::Node v = value(key);
  double x = 0;
  try {
    if (!v.IsScalar()) throw YAML::Exception(v.Mark(), "not a scalar");
    x = v.as<double>();
  } catch (const YAML::Exception&) {
    fail(key, "expected a number in [" + fmt(lo) + ", " + fmt(hi) + "]");
  }
  if (!std::isfinite(x) || x < lo || x > hi) {
    fail(key, "value " + v.Scalar() + " is outside the allowed range [" + fmt(lo) + ", " +
                  fmt(hi) + "]");
  }
  return x;
}

std::int64_t ConfigNode::get_int(const std::string& key, std::int64_t fallback,
                                 std::int64_t lo, std::int64_t hi) const {
  if (!has(key)) return fallback;
  const YAML::Node v = value(key);
  std::int64_t x = 0;
  try {
    if (!v.IsScalar()) throw YAML::Exception(v.Mark(), "not a scalar");
    x = v.as<std::int64_t>();
  } catch (const YAML::Exception&) {
    fail(key, "expected an integer in [" + std::to_string(lo) + ", " + std::to_string(hi) +
                  "]");
  }
  if (x < lo || x > hi) {
    fail(key, "value " + v.Scalar() + " is outside the allowed range [" + std::to_string(lo) +
                  ", " + std::to_string(hi) + "]");
  }
  return x;
}

std::uint64_t ConfigNode::get_seed(const std::string& key, std::uint64_t fallback) const {
  if (!has(key)) return fallback;
  const YAML::Node v = value(key);
  try {
    if (!v.IsScalar() || v.Scalar().empty() || v.Scalar()[0] == '-') {
      throw YAML::Exception(v.Mark(), "bad seed");
    }
    return v.as<std::uint64_t>();
  } catch (const YAML::Exception&) {
    fail(key, "expected an unsigned integer seed in [0, 18446744073709551615]");
  }
}

bool ConfigNode::get_bool(const std::string& key, bool fallback) const {
  if (!has(key)) return fallback;
  const YAML::Node v = value(key);
  if (v.IsScalar()) {
    const std::string& x = v.Scalar();
    if (x == "true" || x == "yes" || x == "on") return true;
    if (x == "false" || x == "no" || x == "off") return false;
  }
  fail(key, "expected true or false");
}

std::string ConfigNode::get_string(const std::string& key, const std::string& fallback) const {
  if (!has(key)) return fallback;
  const YAML::Node v = value(key);
  if (!v.IsScalar()) fail(key, "expected a string");
  return v.Scalar();
}

std::vector<std::string> ConfigNode::get_string_list(const std::string& key, std::size_t min_count) const {
  const YAML::Node v = value(key);
  if (!v.IsSequence() || v.size() < min_count) {
    fail(key, "expected a list of at least " + std::to_string(min_count) + " strings");
  }
  std::vector<std::string> out;
  for (const auto& e : v) {
    if (!e.IsScalar()) fail(key, "expected a list of strings");
    out.push_back(e.Scalar());
  }
  return out;
}

std::string ConfigNode::get_choice(const std::string& key, const std::string& fallback,
                                   const std::vector<std::string>& allowed) const {
  const std::string s = get_string(key, fallback);
  for (const auto& a : allowed) {
    if (a == s) return s;
  }
  std::string list;
  for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
  fail(key, "unknown value '" + s + "'; allowed: " + list);
}

std::vector<double> ConfigNode::get_real_list(const std::string& key, std::size_t count,
                                              double lo, double hi) const {
  const YAML::Node v = value(key);
  const std::string range = "[" + fmt(lo) + ", " + fmt(hi) + "]";
  if (!v.IsSequence() || v.size() != count) {
    fail(key, "expected a list of " + std::to_string(count) + " numbers in " + range);
  }
  std::vector<double> out;
  for (const auto& e : v) {
    double x = 0;
    try {
      x = e.as<double>();
    } catch (const YAML::Exception&) {
      fail(key, "expected a list of " + std::to_string(count) + " numbers in " + range);
    }
    if (!std::isfinite(x) || x < lo || x > hi) {
      fail(key, "element " + e.Scalar() + " is outside the allowed range " + range);
    }
    out.push_back(x);
  }
  return out;
}

std::vector<double> ConfigNode::get_real_list_any(const std::string& key, std::size_t min_count,
                                                  std::size_t max_count, double lo, double hi) const {
  const YAML::Node v = value(key);
  if (!v.IsSequence() || v.size() < min_count || v.size() > max_count) {
    fail(key, "expected a list of " + std::to_string(min_count) + " to " + std::to_string(max_count) +
                  " numbers in [" + fmt(lo) + ", " + fmt(hi) + "]");
  }
  return get_real_list(key, v.size(), lo, hi);
}

namespace {

nlohmann::ordered_json yaml_json(const YAML::Node& n) {
  if (n.IsMap()) {
    nlohmann::ordered_json o = nlohmann::ordered_json::object();
    for (const auto& kv : n) o[kv.first.Scalar()] = yaml_json(kv.second);
    return o;
  }
  if (n.IsSequence()) {
    nlohmann::ordered_json a = nlohmann::ordered_json::array();
    for (const auto& e : n) a.push_back(yaml_json(e));
    return a;
  }
  if (n.IsNull()) return nullptr;
  const std::string& s = n.Scalar();
  if (n.Tag() == "!") return s;  // quoted: a string whatever it spells
  static const std::regex null_re("~|null|Null|NULL"), true_re("true|True|TRUE"), false_re("false|False|FALSE"),
      int_re("[-+]?[0-9]+"), real_re("[-+]?(\\.[0-9]+|[0-9]+(\\.[0-9]*)?)([eE][-+]?[0-9]+)?");
  if (std::regex_match(s, null_re)) return nullptr;
  if (std::regex_match(s, true_re)) return true;
  if (std::regex_match(s, false_re)) return false;
  if (std::regex_match(s, int_re)) {
    std::int64_t i = 0;
    const auto [end, ec] = std::from_chars(s.data() + (s[0] == '+'), s.data() + s.size(), i);
    if (ec == std::errc() && end == s.data() + s.size()) return i;
  }
  if (std::regex_match(s, real_re)) {
    const double x = std::strtod(s.c_str(), nullptr);
    if (std::isfinite(x)) return x;
  }
  return s;
}

}  // namespace

nlohmann::ordered_json ConfigNode::get_json(const std::string& key) const {
  const YAML::Node v = value(key);
  if (!v.IsMap()) fail(key, "expected a mapping of keys to values");
  return yaml_json(v);
}

ConfigNode ConfigNode::child(const std::string& key) const {
  const YAML::Node v = value(key);
  if (!v.IsMap()) fail(key, "expected a mapping of keys to values");
  ConfigNode c(v, state_, full_path(key));
  state_->handed_out.push_back({c.node_, c.path_, c.used_});
  return c;
}

std::vector<ConfigNode> ConfigNode::children(const std::string& key) const {
  const YAML::Node v = value(key);
  if (!v.IsSequence()) fail(key, "expected a list of mappings");
  std::vector<ConfigNode> out;
  for (std::size_t i = 0; i < v.size(); ++i) {
    const std::string p = full_path(key) + "[" + std::to_string(i) + "]";
    if (!v[i].IsMap()) {
      throw InputError(state_->file + ":" + line_of(v[i]) + ": '" + p +
                       "': expected a mapping of keys to values");
    }
    ConfigNode c(v[i], state_, p);
    state_->handed_out.push_back({c.node_, c.path_, c.used_});
    out.push_back(c);
  }
  return out;
}

void ConfigNode::report_unused() const {
  std::string errors;
  auto check = [&](const Handed& n) {
    for (const auto& kv : n.node) {
      const std::string k = kv.first.Scalar();
      if (!n.used->count(k)) {
        const std::string name = n.path.empty() ? k : n.path + "." + k;
        // A key inserted by a sweep has no line of its own; its value has.
        const YAML::Node& at = kv.first.Mark().line >= 0 ? kv.first : kv.second;
        errors += (errors.empty() ? "" : "\n") + state_->file + ":" + line_of(at) +
                  ": unknown key '" + name + "'";
      }
    }
  };
  check({node_, path_, used_});
  for (const auto& c : state_->handed_out) check(c);
  if (!errors.empty()) throw InputError(errors);
}

Rgb read_rgb(const ConfigNode& node, const std::string& key, Rgb fallback) {
  if (!node.has(key)) return fallback;
  const auto c = node.get_real_list(key, 3, 0, 1);
  return {static_cast<float>(c[0]), static_cast<float>(c[1]), static_cast<float>(c[2])};
}

}  // namespace grapebench
