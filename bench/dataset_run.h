// `grapebench dataset`: labelled image datasets for learned detectors, streamed from a
// scene's captures. Per image (the left camera of a colour sensor): the colour PNG,
// exact depth (16-bit PNG in mm and 32-bit float TIFF in m, 0 where nothing is hit),
// an instance-ID image (16-bit, the image's annotation `instance_id`; 0 none) and a
// semantic image (8-bit, Part + 1; 0 none). Per dataset: COCO JSON per split with
// visible and amodal masks (RLE), boxes and visible fractions, the intrinsics (OpenCV
// convention) and pose per image; YOLO boxes and polygons; the 3D truth of every bunch
// and berry instance; a manifest. Splits by bunch seed, so no bunch is in two splits.
// Cases are written one at a time (images as they come, the case's annotations when it
// ends), so memory holds a case, never the dataset; an interrupted dataset resumes.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <string>

#include "bench/image_truth.h"
#include "bench/progress.h"
#include "bench/scene.h"

namespace grapebench {

struct DatasetRunOptions {
  std::filesystem::path out;  // the dataset's folder: refused when it holds files, unless `resume`
  int threads = 0;            // 0: all cores
  bool resume = false;        // continue a dataset of the same scene: finished cases are kept
  std::filesystem::path cycles_cache;  // Cycles' images kept and reused here; empty: none
  Verbosity verbosity = Verbosity::normal;
};

// Where the time goes, s (summed over images).
struct DatasetTiming {
  double capture = 0;  // the sensor's images (the renderer)
  double labels = 0;   // the exact labels: one ray per pixel centre into the scene the image shows
  double masks = 0;    // visible and amodal masks, RLE, outlines
  double write = 0;    // PNG, TIFF and label files
};

struct DatasetSummary {
  int cases = 0, cases_resumed = 0;
  int images = 0;                     // written by this run
  std::array<int, 3> split_images{};  // train, val, test: in the whole dataset
  std::size_t annotations = 0;        // in the whole dataset
  double seconds = 0;                 // wall time of this run
  double peak_rss_mb = 0;             // the process's peak resident memory
  DatasetTiming timing;
};

// Throws InputError (exit 2) for a scene without a colour sensor and a rig, or a
// folder that holds another dataset or other files.
DatasetSummary write_dataset(const SceneSet& set, const DatasetRunOptions& options);

// The split of a bunch seed for the scene's fractions: 0 train, 1 val, 2 test.
int dataset_split(std::uint64_t bunch_seed, const DatasetParams& p);
inline constexpr std::array<const char*, 3> kSplitNames{"train", "val", "test"};

}  // namespace grapebench
