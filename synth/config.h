// Strict reading of YAML scene files. Every value read is checked against its
// allowed range, every error names the file, line and key, and keys that nobody
// read are reported as errors (pbrt's ReportUnused), so a typo never passes
// silently.
#pragma once

#include "synth/types.h"

#include <nlohmann/json_fwd.hpp>
#include <yaml-cpp/yaml.h>

#include <cstdint>
#include <map>
#include <memory>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

namespace grapebench {

// Any bad input: scene files, parameters, point clouds, degenerate geometry.
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Throws InputError "who: name = v unit outside the allowed range [lo, hi]" unless
// lo <= v <= hi (NaN fails). For parameters passed in code; scene files use
// ConfigNode, whose errors also name file and line.
void check_range(double v, double lo, double hi, const char* who, const char* name, const char* unit = "");

// A mapping node of a YAML document that remembers which keys were read.
class ConfigNode {
 public:
  // Parses text; `name` stands for the file in messages.
  static ConfigNode load_string(const std::string& text, const std::string& name);
  // The strict parse under both: one document; no duplicate or non-scalar keys, no
  // explicit tags, at most 64 levels deep; else InputError with file:line.
  static YAML::Node parse_strict(const std::string& text, const std::string& name);
  // Wraps an already parsed document (e.g. a scene with sweep values substituted;
  // substituted nodes keep the line marks of where their values were written).
  // `swept`: the keys the scene's sweep varies (dotted paths, as the sweep writes
  // them: "sensor.renderer").
  static ConfigNode from_yaml(YAML::Node root, const std::string& name, std::set<std::string> swept = {});
  const YAML::Node& yaml() const { return node_; }

  bool has(const std::string& key) const;
  // Typed getters: a missing key returns `fallback`; a present key must convert and
  // lie in [lo, hi], or InputError names file:line, the key and the range.
  double get_real(const std::string& key, double fallback, double lo, double hi) const;
  std::int64_t get_int(const std::string& key, std::int64_t fallback, std::int64_t lo,
                       std::int64_t hi) const;
  std::uint64_t get_seed(const std::string& key, std::uint64_t fallback) const;
  bool get_bool(const std::string& key, bool fallback) const;
  std::string get_string(const std::string& key, const std::string& fallback) const;
  // A list of strings (at least min_count).
  std::vector<std::string> get_string_list(const std::string& key, std::size_t min_count) const;
  std::string get_choice(const std::string& key, const std::string& fallback,
                         const std::vector<std::string>& allowed) const;
  std::vector<double> get_real_list(const std::string& key, std::size_t count, double lo,
                                    double hi) const;
  // A list of between min_count and max_count numbers, each in [lo, hi].
  std::vector<double> get_real_list_any(const std::string& key, std::size_t min_count, std::size_t max_count,
                                        double lo, double hi) const;
  // A free document (a mapping) as JSON, every key in it counted as read: plain
  // scalars become null, true / false, integers or finite numbers as YAML 1.2's core
  // schema reads them, anything else (and every quoted scalar) a string.
  nlohmann::ordered_json get_json(const std::string& key) const;
  // A nested mapping (must be a mapping) or a sequence of mappings.
  ConfigNode child(const std::string& key) const;
  std::vector<ConfigNode> children(const std::string& key) const;

  // Whether the document's sweep varies this node's `key`: a key read only under a
  // value of it may then stand in every condition (its other values' cells leave it).
  bool swept(const std::string& key) const;
  // A key left under such a sweep: counted as read for report_unused and recorded,
  // with `why` (its condition), so that a sweep none of whose cells reads it can fail.
  void skip(const std::string& key, const std::string& why) const;
  // A key read under its condition (the other half of that check).
  void note_conditional_read(const std::string& key) const;
  // By dotted path: the keys left, each with its message ("file:line: 'path': why"),
  // and the conditional keys read.
  const std::map<std::string, std::string>& skipped_keys() const { return state_->skipped; }
  const std::set<std::string>& conditional_keys_read() const { return state_->conditional_read; }

  // Throws InputError listing every key of this node and of the children handed out
  // that was never read.
  void report_unused() const;

  // "file:line" of a key (or of the node itself when key is empty).
  std::string where(const std::string& key = {}) const;
  [[noreturn]] void fail(const std::string& key, const std::string& message) const;
  const std::string& file() const { return state_->file; }

 private:
  struct Handed {  // a child handed out, for report_unused (no cycle through State)
    YAML::Node node;
    std::string path;
    std::shared_ptr<std::set<std::string>> used;
  };
  struct State {
    std::string file;
    std::set<std::string> swept;  // dotted paths the sweep varies
    std::map<std::string, std::string> skipped;
    std::set<std::string> conditional_read;
    std::vector<Handed> handed_out;
  };
  ConfigNode(YAML::Node node, std::shared_ptr<State> state, std::string path);
  YAML::Node value(const std::string& key) const;
  std::string full_path(const std::string& key) const;  // "sensor.camera.key"

  YAML::Node node_;
  std::shared_ptr<State> state_;
  std::string path_;  // dotted key path for messages, e.g. "bunches[0]"
  std::shared_ptr<std::set<std::string>> used_;
};

// A colour written as [r, g, b], each in [0, 1] (linear); `fallback` when absent.
Rgb read_rgb(const ConfigNode& node, const std::string& key, Rgb fallback);

}  // namespace grapebench
