#include "synth/temp_folder.h"

#include <unistd.h>

#include <atomic>
#include <mutex>
#include <set>

namespace grapebench {

namespace fs = std::filesystem;

namespace {

std::mutex g_mutex;
std::set<fs::path> g_live;  // every TempFolder's path (remove_temp_folders_before_exit)

}  // namespace

TempFolder::TempFolder(const std::string& prefix) {
  static std::atomic<unsigned> counter{0};
  path = fs::temp_directory_path() /
         (prefix + "-" + std::to_string(getpid()) + "-" + std::to_string(counter.fetch_add(1)));
  const std::lock_guard lock(g_mutex);
  fs::remove_all(path);
  fs::create_directories(path);
  g_live.insert(path);
}

TempFolder::~TempFolder() {
  const std::lock_guard lock(g_mutex);
  std::error_code ec;
  fs::remove_all(path, ec);
  g_live.erase(path);
}

void remove_temp_folders_before_exit() {
  g_mutex.lock();  // never unlocked: the process ends next
  for (const auto& p : g_live) {
    std::error_code ec;
    fs::remove_all(p, ec);
  }
}

}  // namespace grapebench
