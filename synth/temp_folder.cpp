#include "synth/temp_folder.h"

#include <unistd.h>

#include <atomic>

namespace grapebench {

namespace fs = std::filesystem;

TempFolder::TempFolder(const std::string& prefix) {
  static std::atomic<unsigned> counter{0};
  path = fs::temp_directory_path() /
         (prefix + "-" + std::to_string(getpid()) + "-" + std::to_string(counter.fetch_add(1)));
  fs::remove_all(path);
  fs::create_directories(path);
}

TempFolder::~TempFolder() {
  std::error_code ec;
  fs::remove_all(path, ec);
}

}  // namespace grapebench
