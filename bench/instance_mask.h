// An estimator's image instance as a COCO mask over its image: the mask it gives
// (0 / 1 on its box), else its COCO RLE string, else its box's pixels (as COCO's
// loadRes makes a box result into a mask). Read by the detection protocol (every
// answer) and the stereo_pair protocol (the cluster region).
#pragma once

#include <string>

#include "algorithms/estimate.h"
#include "bench/coco_rle.h"

namespace grapebench {

// width x height pixels. Throws InputError, prefixed with `where`, for a mask outside
// the image or of a length other than mask_w x mask_h, or an RLE string that does
// not decode to the image.
Rle instance_mask(const ImageDetection& a, int width, int height, const std::string& where);

}  // namespace grapebench
