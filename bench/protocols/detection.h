// The detection protocol (issue 42): every view of the rig is one colour image (the
// left camera of sensor stereo_rgb; its right image too when the sensor renders it),
// measured alone. Named stages: scan (as `grapebench dataset`, from the same stream),
// per view the exact instances (bench/image_truth.h: visible masks of the scored
// categories), the estimator input (the image and its camera, never the labels), the
// estimators, and the scoring of each output kind: instances (kept in the case for
// COCO's AP over every image: bench/outputs.cpp), the berry count per bunch and, where
// an answered bunch carries one, its volume (scalars, so intervals and paired
// comparisons as for any scalar).
#pragma once

#include "bench/case_result.h"
#include "sensors/scan.h"

namespace grapebench {

// An estimator's instances as COCO results of an image of width x height: masks
// encoded (a box-only answer as its box's pixels), areas, boxes; answers in categories
// outside `categories` dropped (counted in `dropped`); `source`: each kept object's
// index in `answers`. Throws InputError naming the
// instance for an unknown category, a box that is not finite or has a negative size,
// a score that is not finite, or a mask outside the image or of the wrong length.
std::vector<CocoObject> answer_objects(const std::vector<ImageDetection>& answers, int width, int height,
                                       const std::vector<std::string>& categories, int& dropped,
                                       std::vector<std::size_t>& source);

// Rows of one view: instances (estimate: answers kept, truth: true instances), per true
// bunch berry_count (estimate: berry answers whose box centre falls on the bunch's
// visible mask; truth: its visible berries) when berries are scored, and volume (m3)
// for answered bunches with a volume paired to a true bunch (mask IoU >= match_iou,
// best score first). `bunch_volumes`: the true solid volume per case bunch.
std::vector<EstimateRow> detection_rows(const EstimateRow& base, const std::vector<ImageDetection>& answers,
                                        const std::vector<CocoObject>& answered, const std::vector<std::size_t>& source,
                                        const DetectionView& truth,
                                        const std::vector<int>& truth_bunch, const std::vector<double>& bunch_volumes,
                                        double match_iou);

CaseResult run_detection(const Condition& condition, int condition_index, const BunchJob& job);

}  // namespace grapebench
