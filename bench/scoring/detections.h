// Scores of a detection output (seed 001's berry circles) against the ground-truth
// objects (the projected true berries): precision, recall and F1 under a stated
// matching rule, and the centre and radius errors of the matched pairs.
#pragma once

#include "algorithms/estimate.h"

#include <string>
#include <vector>

namespace grapebench {

struct TruthObject {
  Circle circle;
  // Counted for recall (seed 001: at least two thirds unoccluded in the left label
  // image); an object that is not visible may still be matched, and then its detection
  // is no false positive.
  bool visible = true;
};

// The matching rule: detections are taken by descending score (ties: input order);
// each matches the unmatched truth object it overlaps most, if
//   disc_iou: the discs' intersection over union is at least `threshold`;
//   centre_in_radius: its centre lies within threshold x the object's radius of the
//   object's centre (the nearest such object).
struct DetectionMatch {
  enum class Rule { DiscIou, CentreInRadius };
  Rule rule = Rule::DiscIou;
  double threshold = 0.5;
  std::string describe() const;  // "disc IoU >= 0.5", for reports
};

struct DetectionScore {
  int detections = 0, matched = 0;  // matched: true positives
  int false_positives = 0;
  int visible = 0, visible_found = 0;  // visible objects, and those matched
  double precision = 0, recall = 0, f1 = 0;  // NaN where the denominator is 0
  double centre_error_mean = 0;  // px, over the matched pairs
  double radius_error_mean = 0;  // px, detection - object, signed
  double radius_error_mae = 0;   // px
  std::vector<int> match;        // per detection, the matched object's index or -1
};

// Intersection over union of two discs (exact lens area).
double disc_iou(const Circle& a, const Circle& b);

DetectionScore score_detections(const std::vector<Detection>& detections, const std::vector<TruthObject>& truth,
                                const DetectionMatch& rule);

// Pools several images' scores (counts summed, errors weighted by matches).
DetectionScore pool_detection_scores(const std::vector<DetectionScore>& scores);

}  // namespace grapebench
