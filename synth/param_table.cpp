#include "synth/param_table.h"

#include <cstdio>
#include <cstdlib>

namespace grapebench {

std::string param_number(double v) {
  // The shortest text that reads back as the same double; plain notation where that
  // is short ("10", not "1e+01").
  std::string first;
  for (int p = 1; p <= 17; ++p) {
    char c[40];
    std::snprintf(c, sizeof c, "%.*g", p, v);
    if (std::strtod(c, nullptr) != v) continue;
    const std::string s = c;
    if (s.find('e') == std::string::npos) return first.empty() || s.size() <= 12 ? s : first;
    if (first.empty()) first = s;
  }
  if (!first.empty()) return first;
  char b[40];
  std::snprintf(b, sizeof b, "%.17g", v);
  return b;
}

std::string param_number(float v) {
  for (int p = 1; p <= 9; ++p) {
    char c[40];
    std::snprintf(c, sizeof c, "%.*g", p, static_cast<double>(v));
    if (std::strtof(c, nullptr) == v) return c;
  }
  return param_number(static_cast<double>(v));
}

std::string render_keys(const std::vector<KeyInfo>& keys, const std::string& indent) {
  std::string s;
  char line[512];
  for (const auto& k : keys) {
    std::snprintf(line, sizeof line, "%s%-26s %-7s %-12s %s", indent.c_str(), k.key.c_str(), k.unit.c_str(),
                  k.default_value.c_str(), k.range.c_str());
    s += line;
    if (!k.when.empty()) s += "  (only with " + k.when + ")";
    s += "\n" + indent + "    " + k.doc + "\n";
  }
  return s;
}

}  // namespace grapebench
