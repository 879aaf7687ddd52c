#include "algorithms/temp_folder.h"

#include <unistd.h>

#include <atomic>
#include <fstream>

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

std::string file_tail(const fs::path& p, std::size_t n) {
  std::ifstream in(p, std::ios::binary | std::ios::ate);
  if (!in) return {};
  const std::streamoff size = in.tellg();
  const std::streamoff from = size > static_cast<std::streamoff>(n) ? size - static_cast<std::streamoff>(n) : 0;
  in.seekg(from);
  std::string t(static_cast<std::size_t>(size - from), '\0');
  in.read(t.data(), static_cast<std::streamsize>(t.size()));
  if (from > 0) t = "..." + t;
  while (!t.empty() && (t.back() == '\n' || t.back() == ' ')) t.pop_back();
  return t;
}

}  // namespace grapebench
