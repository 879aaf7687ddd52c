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
#include "bench/scoring/statistics.h"

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
// Stat k's name with the AR entries named after the limits in force (AR_<max_dets[i]>),
// so a raised limit is never labelled AR_100.
// k in [0, 12); max_dets: COCO's three limits.
inline std::string coco_stat_name(std::size_t k, const std::vector<int>& max_dets) {
  if (k >= 6 && k <= 8 && max_dets.size() == 3) return "AR_" + std::to_string(max_dets[k - 6]);
  return kCocoStatNames.at(k);
}
struct CocoEvalResult {
  std::array<double, 12> stats{};
  std::vector<std::pair<CocoCategory, std::array<double, 12>>> per_category;
};
CocoEvalResult coco_evaluate(const CocoGroundTruth& gt, const std::vector<CocoObject>& detections,
                             const CocoEvalParams& params);

// The same in two steps, so images can be resampled: each image matched once per
// category and area range (COCOeval.evaluate), then accumulated over any list of image
// positions (0-based, in id order; an image listed twice counts twice).
struct CocoImageEval {  // one image and category at one area range
  std::vector<double> scores;              // detections, best first, at most max_dets.back()
  std::vector<std::vector<char>> matched;  // [threshold][detection]
  std::vector<std::vector<char>> ignored;  // [threshold][detection]
  std::vector<char> gt_ignored;            // [ground truth]
};
struct CocoEvaluation {
  std::vector<CocoCategory> categories;  // by id
  std::size_t images = 0;
  std::vector<int> max_dets;
  std::vector<CocoImageEval> evals;  // [(category * 4 + area range) * images + image]
};
CocoEvaluation coco_evaluate_images(const CocoGroundTruth& gt, const std::vector<CocoObject>& detections,
                                    const CocoEvalParams& params);
// all_ranges false: only the all-area range at the last max_dets (AP, AP50, AP75 and
// AR at the last limit; the others -1), for resampling.
CocoEvalResult coco_accumulate(const CocoEvaluation& e, const std::vector<std::size_t>& images, bool all_ranges);

// Percentile intervals of AP and AP50 (overall and per category) from `resamples`
// resamplings with replacement, drawn from `seed`: of `groups` of image positions (the
// independent units, e.g. the views of one case, which share its bunches), or with no
// groups of the images (a detector's errors within an image are not independent).
struct CocoIntervals {
  Interval ap, ap50;
  std::vector<std::pair<Interval, Interval>> per_category;  // (AP, AP50), by category id
};
CocoIntervals coco_bootstrap(const CocoEvaluation& e, std::uint64_t seed, int resamples = 1000, double level = 0.95,
                             const std::vector<std::vector<std::size_t>>& groups = {});
// Two detectors on the same images: intervals of AP(a) - AP(b) over the same resamples.
CocoIntervals coco_bootstrap_difference(const CocoEvaluation& a, const CocoEvaluation& b, std::uint64_t seed,
                                        int resamples = 1000, double level = 0.95,
                                        const std::vector<std::vector<std::size_t>>& groups = {});

}  // namespace grapebench
