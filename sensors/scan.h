// A multi-view scan of one bunch, and its files.
#pragma once

#include "sensors/rig.h"
#include "sensors/sensor.h"

#include <filesystem>
#include <functional>
#include <span>
#include <string>
#include <vector>

namespace grapebench {

struct ScanView {
  RigView rig;
  Camera camera;
  OrganisedCloud cloud;
  double seconds = 0;  // wall time of the capture (not written to the data files)
};

struct Scan {
  std::vector<ScanView> views;
  nlohmann::ordered_json sensor, rig, background;
  std::uint64_t seed = 0;
};

// The seed of view k of a scan with `seed`. Every capture of a scan's view takes it
// from here, tests and benchmarks that capture one view alone included.
std::uint64_t view_seed(std::uint64_t seed, std::size_t k);

// Every view of `rig` through `sensor`; view k draws from view_seed(seed, k).
Scan scan_bunch(const RayScene& scene, const Sensor& sensor, const Rig& rig, const BackgroundSpec& background,
                std::uint64_t seed);

// What a scan is (sensor, rig, background, seed), without its views.
Scan scan_description(const Sensor& sensor, const Rig& rig, const BackgroundSpec& background, std::uint64_t seed);

// The same views, captured one at a time and handed to `consume` (view k), so a long
// pass never holds more than one frame. Returns the scan's description (sensor, rig,
// background, seed) without views.
Scan scan_views(const RayScene& scene, const Sensor& sensor, const Rig& rig, const BackgroundSpec& background,
                std::uint64_t seed, const std::function<void(ScanView&&, std::size_t k)>& consume);
// The same views by several sensors with one together_key (Sensor::capture_together):
// `consume` gets view k's frames, one a sensor in their order, each the same as that
// sensor's capture alone; `seconds` is the shared capture's time over the sensors'
// count. `consume` returns whether to go on (false: no further view is captured).
// scan_views is its one-sensor case.
void scan_views_together(const RayScene& scene, std::span<const Sensor* const> sensors, const Rig& rig,
                         const BackgroundSpec& background, std::uint64_t seed,
                         const std::function<bool(std::vector<ScanView>&&, std::size_t k)>& consume);

// Files of one view: organised binary PCD (x y z rgb normal label berry, NaN where
// invalid; points in the sensor frame, VIEWPOINT the camera-to-world pose, so PCL and
// CloudCompare place each view in the world), binary PLY of the valid points (sensor
// frame), 16-bit depth PNG (mm, 0 = no return) and RGB PNG.
std::string pcd_bytes(const OrganisedCloud& cloud, const Eigen::Isometry3d& camera_to_world = Eigen::Isometry3d::Identity());
std::string ply_points_bytes(const OrganisedCloud& cloud);
// Every view's valid points in the world frame, one binary PLY (x y z, normal, colour,
// label, berry, view index).
std::string merged_ply_bytes(const Scan& scan);
std::string depth_png_bytes(const OrganisedCloud& cloud);
std::string rgb_png_bytes(const OrganisedCloud& cloud);
std::string label_png_bytes(const OrganisedCloud& cloud);  // 8-bit Part per pixel, 255 = none
std::string image_png_bytes(int width, int height, const std::vector<std::uint8_t>& rgb);  // W x H x 3

// Writes `<dir>/<stem>_<view>.{pcd,ply}`, `_depth.png`, `_rgb.png`, `_label.png`
// per view as each comes, then `<dir>/<stem>_scan.json` (intrinsics in OpenCV's
// convention, poses, sensor, rig, files); with `merged`, also `<dir>/<stem>_merged.ply`
// (its points gathered in a temporary file as the views come, not in memory).
class ScanWriter {
 public:
  // `description`: the scan's sensor, rig, background and seed (its views unused).
  ScanWriter(const Scan& description, const std::filesystem::path& dir, std::string stem, bool merged);
  ScanWriter(const ScanWriter&) = delete;
  ScanWriter& operator=(const ScanWriter&) = delete;
  ~ScanWriter();  // removes the temporary file of an unfinished merged cloud
  void add(const ScanView& view);
  void finish();

 private:
  std::filesystem::path dir_;
  std::string stem_;
  bool merged_;
  nlohmann::ordered_json manifest_;
  std::filesystem::path merged_body_;  // the merged cloud's points so far (binary records)
  std::size_t merged_points_ = 0;
  std::size_t views_ = 0;
};
void write_scan(const Scan& scan, const std::filesystem::path& dir, const std::string& stem, bool merged = false);

}  // namespace grapebench
