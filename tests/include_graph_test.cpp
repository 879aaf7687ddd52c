// The source layout: data flows one way (synth -> sensors -> algorithms -> bench), so no
// room includes a room downstream of it, and no two modules inside a room (a module is
// a file pair, x.h with x.cpp) include each other, directly or through others.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

const std::vector<std::string> kRooms = {"synth", "sensors", "algorithms", "bench"};  // upstream first

// module -> modules of the same room it includes ("bench/case_run" -> {"bench/scene", ...}).
using Graph = std::map<std::string, std::set<std::string>>;

struct Layout {
  std::map<std::string, Graph> rooms;
  std::vector<std::string> upstream_violations;  // "sensors/x.cpp includes bench/y.h"
};

Layout read_layout(const fs::path& root) {
  Layout out;
  const std::regex include(R"re(^\s*#\s*include\s*"([a-z0-9_]+)/([A-Za-z0-9_/]+)\.h")re");
  for (std::size_t r = 0; r < kRooms.size(); ++r) {
    const std::string& room = kRooms[r];
    Graph& g = out.rooms[room];
    for (const auto& f : fs::recursive_directory_iterator(root / room)) {
      const auto ext = f.path().extension();
      if (ext != ".h" && ext != ".cpp") continue;
      if (f.path().string().find("/perf/") != std::string::npos) continue;  // benchmarks are programs, not modules
      const std::string module = fs::relative(f.path(), root).replace_extension().generic_string();
      g[module];
      std::ifstream in(f.path());
      std::string line;
      while (std::getline(in, line)) {
        std::smatch m;
        if (!std::regex_search(line, m, include)) continue;
        const std::string to_room = m[1], target = to_room + "/" + std::string(m[2]);
        const auto at = std::find(kRooms.begin(), kRooms.end(), to_room);
        if (at == kRooms.end()) continue;
        if (static_cast<std::size_t>(at - kRooms.begin()) > r) {
          out.upstream_violations.push_back(fs::relative(f.path(), root).generic_string() + " includes " + target + ".h");
        }
        if (to_room == room && target != module) g[module].insert(target);
      }
    }
  }
  return out;
}

// Every cycle's modules, as "a -> b -> a" (one line per strongly connected component
// of more than one module; Tarjan's algorithm).
std::vector<std::string> cycles(const Graph& g) {
  std::map<std::string, int> index, low;
  std::vector<std::string> stack, out;
  std::set<std::string> on_stack;
  int next = 0;
  std::function<void(const std::string&)> visit = [&](const std::string& v) {
    index[v] = low[v] = next++;
    stack.push_back(v);
    on_stack.insert(v);
    const auto it = g.find(v);
    if (it != g.end()) {
      for (const auto& w : it->second) {
        if (!index.count(w)) {
          visit(w);
          low[v] = std::min(low[v], low[w]);
        } else if (on_stack.count(w)) {
          low[v] = std::min(low[v], index[w]);
        }
      }
    }
    if (low[v] != index[v]) return;
    std::vector<std::string> component;
    std::string w;
    do {
      w = stack.back();
      stack.pop_back();
      on_stack.erase(w);
      component.push_back(w);
    } while (w != v);
    if (component.size() > 1) {
      std::string s;
      for (auto c = component.rbegin(); c != component.rend(); ++c) s += *c + " -> ";
      out.push_back(s + component.back());
    }
  };
  for (const auto& [v, _] : g) {
    if (!index.count(v)) visit(v);
  }
  return out;
}

TEST(IncludeGraph, TheCycleFinderFindsCyclesAndOnlyThem) {
  Graph g = {{"a", {"b"}}, {"b", {"c"}}, {"c", {"a"}}, {"d", {"a"}}, {"e", {}}};
  ASSERT_EQ(cycles(g).size(), 1u);
  EXPECT_NE(cycles(g)[0].find("a"), std::string::npos);
  EXPECT_EQ(cycles(g)[0].find("d"), std::string::npos);
  g["c"].clear();
  EXPECT_TRUE(cycles(g).empty());
  EXPECT_EQ(cycles({{"x", {"y"}}, {"y", {"x"}}}).size(), 1u);
}

TEST(IncludeGraph, NoRoomIncludesARoomDownstreamOfIt) {
  const Layout l = read_layout(GRAPEBENCH_SOURCE_DIR);
  for (const auto& v : l.upstream_violations) ADD_FAILURE() << v;
}

TEST(IncludeGraph, NoIncludeCycleInsideARoom) {
  const Layout l = read_layout(GRAPEBENCH_SOURCE_DIR);
  std::size_t modules = 0;
  for (const auto& [room, g] : l.rooms) {
    modules += g.size();
    for (const auto& c : cycles(g)) ADD_FAILURE() << room << ": " << c;
  }
  EXPECT_GT(modules, 50u);  // the walk found the sources
}

}  // namespace
