// Seed 001's image stages as an instance detector (protocol detection): the colour
// segmentation's regions as bunches (Luo et al. 2016, Sect. 2.2.2.1) and the Hough
// circles in each as berries (Sect. 2.2.2.4), with the revolved bounding volume as the
// bunch's volume where the stereo pair places the cutting point (Sect. 2.2.4). The
// paper's system finds one cluster per image (`regions: largest`); `all` takes every
// region, for images of a vine row.
#pragma once

#include "algorithms/estimate.h"
#include "algorithms/stereo/luo2016_stereo.h"

namespace grapebench {

struct Luo2016InstancesParams {
  // The paper's stages and their parameters: luo2016_stereo's, under the same keys.
  Luo2016Params system;
  enum class Regions { Largest, All };
  Regions regions = Regions::Largest;
  // m: the berries' distance for Eq. 6's radius window; 0: the cutting point's, from the
  // stereo pair (the paper), and regions without one get no berries.
  double depth = 0;
};
const ParamTable<Luo2016InstancesParams>& luo2016_instances_param_table();

// Bunches (mask: the region; score: its share of the image's region pixels; volume
// when the full system succeeded on it) and berries (disc masks; score: Hough votes).
// Throws InputError without an image, or with depth 0 and no right image.
Estimate luo2016_instances(const EstimatorInput& input, const Luo2016InstancesParams& p);

}  // namespace grapebench
