#include "synth/temp_folder.h"

#include <unistd.h>

#include <atomic>
#include <mutex>
#include <set>

namespace grapebench {

namespace fs = std::filesystem;

namespace {

// Every TempFolder's path (remove_temp_folders_before_exit), and its mutex. Never
// destroyed: a signal's thread may still use them while main returns.
std::mutex& g_mutex = *new std::mutex;
std::set<fs::path>& g_live = *new std::set<fs::path>;

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
    // Moved aside first: a thread still writing by the folder's path then fails
    // instead of adding a file after remove_all's walk (which would keep the folder).
    fs::path gone = p;
    gone += ".removing";
    std::error_code ec;
    fs::rename(p, gone, ec);
    if (ec) gone = p;
    for (int tries = 0; tries < 3 && fs::exists(gone, ec); ++tries) fs::remove_all(gone, ec);
  }
}

}  // namespace grapebench
