// What the estimators that run other programs (external_estimator, colmap_sfm) share:
// a private temporary folder removed with its owner.
#pragma once

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

}  // namespace grapebench
