// COCO's detection metrics (the rules of pycocotools' COCOeval, re-implemented from its
// documented behaviour; pycocotools is not packaged in Debian 12): per category, image
// and area range, detections sorted by score and cut at the max-detections limit, each
// matched greedily to the unmatched ground truth of highest IoU above the threshold
// (non-ignored ground truth first; a crowd region absorbs any number of detections,
// its IoU taken over the detection's area; detections matched to ignored ground truth,
// or unmatched and outside the area range, are ignored); precision made monotone and
// read at 101 recall points; AP the mean over IoU 0.50:0.05:0.95 and categories.
// Checked on hand cases and against a second implementation (tests/bench/python).
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "bench/coco_rle.h"

namespace grapebench {

struct CocoImage {
  std::int64_t id = 0;
  int width = 0, height = 0;
};
struct CocoCategory {
  int id = 0;
  std::string name;
};
struct CocoObject {  // a ground-truth annotation or a detection
  std::int64_t id = 0, image_id = 0;
  int category_id = 0;
  double score = 1;                     // detections only
  double area = 0;                      // ground truth: its `area`; detections: the mask's or the box's
  std::array<double, 4> bbox{};         // x, y, w, h, px
  bool iscrowd = false;                 // ground truth only
  std::optional<Rle> mask;
};
struct CocoGroundTruth {
  std::vector<CocoImage> images;
  std::vector<CocoCategory> categories;
  std::vector<CocoObject> annotations;
};

// Throw InputError naming `file`, the record's index and key, and what is allowed:
// unknown image or category ids, duplicate ids, NaN or negative boxes, scores that are
// not finite, masks whose size is not their image's or whose runs do not decode.
CocoGroundTruth read_coco_ground_truth(const nlohmann::json& j, const std::string& file);
enum class CocoIouType { Bbox, Segm };
std::vector<CocoObject> read_coco_results(const nlohmann::json& j, const std::string& file,
                                          const CocoGroundTruth& gt, CocoIouType type);

struct CocoEvalParams {
  CocoIouType type = CocoIouType::Bbox;
  std::vector<int> max_dets{1, 10, 100};  // COCO's; the last is the cut for every AP
};

// The 12 numbers of COCOeval.summarize(): AP, AP50, AP75, AP small / medium / large,
// AR at max_dets[0..2], AR small / medium / large (at the last max_dets); -1 where
// nothing is defined (no ground truth in that category and area range).
inline constexpr std::array<const char*, 12> kCocoStatNames{
    "AP", "AP50", "AP75", "AP_small", "AP_medium", "AP_large", "AR_1", "AR_10", "AR_100", "AR_small", "AR_medium", "AR_large"};
struct CocoEvalResult {
  std::array<double, 12> stats{};
  std::vector<std::pair<CocoCategory, std::array<double, 12>>> per_category;
};
CocoEvalResult coco_evaluate(const CocoGroundTruth& gt, const std::vector<CocoObject>& detections,
                             const CocoEvalParams& params);

}  // namespace grapebench
