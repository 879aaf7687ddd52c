// The detection protocol's tables (issue 42): COCO's 12 numbers per condition, station
// and estimator, for masks (segm) and boxes (bbox), overall and per category, with
// bootstrap intervals of AP and AP50 resampling the cases (a case's views share its
// bunches, so the case is the independent unit), and paired AP differences between
// estimators over the same resamples. Images are pooled over the cases
// of a condition; a station's own rows where the rig has several (distance as a
// station, or as a sweep axis: a condition each). An estimator that failed on an
// image answered nothing there.
#pragma once

#include <string>
#include <vector>

#include "bench/case_result.h"

namespace grapebench {

struct DetectionCell {
  std::string condition, station;  // station: the rig's view name, or "all"
  std::string estimator;
  const char* iou_type = "segm";   // "segm" | "bbox"
  int images = 0;
  int max_detections = 100;        // the last of COCO's three limits (its AR_100 is AR at this)
  CocoEvalResult result;
  CocoIntervals intervals;
};
struct DetectionComparison {
  std::string condition, station, a, b;
  const char* iou_type = "segm";
  int images = 0;
  double ap_difference = 0, ap50_difference = 0;  // a - b
  CocoIntervals difference;
};
struct DetectionTables {
  std::vector<DetectionCell> cells;
  std::vector<DetectionComparison> comparisons;
  bool empty() const { return cells.empty(); }
};

// `labels` name each condition and `max_detections` gives its limit; `seed` draws the
// resamples; `resamples` per interval.
DetectionTables detection_tables(const std::vector<CaseResult>& cases, const std::vector<std::string>& labels,
                                 const std::vector<int>& max_detections, std::uint64_t seed, int resamples = 1000);

}  // namespace grapebench
