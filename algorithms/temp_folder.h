// What the estimators that run other programs (external_estimator, colmap_sfm) share:
// a private temporary folder removed with its owner, and the tail of a log file.
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>

namespace grapebench {

// A fresh folder under the system's temporary folder, named prefix-<pid>-<counter>;
// removed with everything in it when the owner goes.
class TempFolder {
 public:
  explicit TempFolder(const std::string& prefix);
  TempFolder(const TempFolder&) = delete;
  TempFolder& operator=(const TempFolder&) = delete;
  ~TempFolder();
  std::filesystem::path path;
};

// The last n bytes of a file, read from there (a program may write gigabytes),
// "..." in front when cut, trailing newlines and spaces trimmed; "" when unreadable.
std::string file_tail(const std::filesystem::path& p, std::size_t n);

}  // namespace grapebench
