// Seed 001's cluster segmentation and its geometry (Luo et al. 2016, Sects. 2.2.2.1-2):
// one colour component (H - I for black varieties, Cr of YCrCb for red ones), Otsu's
// threshold, then dilate, remove small regions, keep the largest connected region,
// fill its holes, dilate; the barycentre (Eq. 1), the top point and L_max.
#pragma once

#include <cstdint>
#include <vector>

#include "algorithms/stereo_pair.h"
#include "synth/param_table.h"

namespace grapebench {

struct ClusterSegmentationParams {
  enum class Component { HueMinusIntensity, Cr };
  Component component = Component::HueMinusIntensity;  // H - I (summer black) or Cr (red), Sect. 2.2.2.1
  int dilate_px = 1;                                   // radius of each dilation's square kernel (not stated; 3 x 3)
  int min_region_px = 150;                             // regions smaller than this are removed (not stated)
  int min_cluster_px = 400;                            // a largest region smaller than this is no cluster
};
const ParamTable<ClusterSegmentationParams>& cluster_segmentation_param_table();

// The cluster region S_GC of an image and its geometry, pixels.
struct ClusterRegion {
  int width = 0, height = 0;
  std::vector<std::uint8_t> mask;      // H x W, 255 on S_GC, 0 elsewhere
  int area = 0;                        // pixels of S_GC
  double xc = 0, yc = 0;               // barycentre (Eq. 1)
  double xt = 0, yt = 0;               // top point: the middle of the region's top row
  double l_max = 0;                    // left to right extent of the region (L_max, Eq. 2)
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;  // bounding rectangle, inclusive
  double otsu_threshold = 0;           // on the component scaled to 0-255
  bool found() const { return area > 0; }
};

// The 8-bit colour component of Sect. 2.2.2.1, H x W: H - I (H of HSI in [0, 1], I =
// (R + G + B) / 765) mapped from [-1, 1] to [0, 255], or Cr of YCrCb.
std::vector<std::uint8_t> cluster_component(const RgbImage& image, ClusterSegmentationParams::Component c);

// An empty region (area 0) when no region of min_cluster_px pixels is left, or the
// component spans fewer than 8 levels (nothing for Otsu to split).
ClusterRegion segment_cluster(const RgbImage& image, const ClusterSegmentationParams& p);

// The region of a given mask (H x W, non-zero on the cluster: the oracle ablation's
// exact cluster pixels) as segment_cluster makes its own, holes filled, then Eqs. 1-2's
// geometry; not dilated and not cut to its largest piece (the exact pixels are the
// region); area 0 below min_cluster_px. Throws InputError when the mask is not H x W.
ClusterRegion cluster_region_of_mask(const std::vector<std::uint8_t>& mask, int width, int height,
                                     const ClusterSegmentationParams& p);

// Every region of at least min_cluster_px pixels, each as segment_cluster makes its
// one (holes filled, dilated; the dilation may make neighbours overlap), largest first:
// the paper's segmentation as a detector of several clusters in one image.
std::vector<ClusterRegion> segment_clusters(const RgbImage& image, const ClusterSegmentationParams& p);

}  // namespace grapebench
