// For tests of programs that must not outlive their run: count them by a marker.
#pragma once

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace grapebench {

// Processes whose command line holds `marker` (the tests' programs carry one).
inline int processes_with(const std::string& marker) {
  int n = 0;
  for (const auto& e : std::filesystem::directory_iterator("/proc")) {
    const std::string name = e.path().filename().string();
    if (name.find_first_not_of("0123456789") != std::string::npos) continue;
    std::ifstream in(e.path() / "cmdline", std::ios::binary);
    std::stringstream text;
    text << in.rdbuf();
    if (text.str().find(marker) != std::string::npos) ++n;
  }
  return n;
}

}  // namespace grapebench
