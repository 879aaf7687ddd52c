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

// Removes every TempFolder of this process that still exists, for a process about to
// end on a signal (whose destructors will not run): from then on no TempFolder is made
// or removed (either blocks), so the process must end right after. Thread-safe.
void remove_temp_folders_before_exit();

}  // namespace grapebench
