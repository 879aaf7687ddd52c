// COCO's run-length encoding of binary masks (the `segmentation` of an annotation or
// a result, as pycocotools' maskApi writes it): runs over the pixels in column-major
// order (down each column, columns left to right), starting with a run of zeros; the
// compact string form stores each run, from the third on as the difference to the run
// two before, in 5-bit groups as characters 48..111 (a sign bit in the last group).
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace grapebench {

struct Rle {
  int height = 0, width = 0;           // pixels
  std::vector<std::uint32_t> counts;   // alternating runs of 0 and 1, summing to height * width
};

// The mask set where `mask[(v - v0) * box_w + (u - u0)]` is nonzero, in a box of
// box_w x box_h pixels at (u0, v0) inside a width x height image (row-major box, the
// box wholly inside the image); pixels outside the box are 0. Costs O(box), not O(image).
Rle rle_encode(const std::uint8_t* mask, int u0, int v0, int box_w, int box_h, int width, int height);
// The whole image (row-major, width x height).
Rle rle_encode(const std::uint8_t* mask, int width, int height);
// Row-major width x height mask of 0 / 1.
std::vector<std::uint8_t> rle_decode(const Rle& r);

std::string rle_string(const Rle& r);
// Throws std::invalid_argument when `s` holds characters outside 48..111, ends inside
// a number, or its runs are negative or do not sum to height * width.
Rle rle_from_string(const std::string& s, int height, int width);

std::uint64_t rle_area(const Rle& r);
// COCO's box of the set pixels: x, y, w, h in pixels (zeros for an empty mask).
std::array<double, 4> rle_box(const Rle& r);
// Intersection over union (0 when both are empty; with `crowd`, over the first's area
// only, as COCO scores a detection against a crowd region). Same size required.
double rle_iou(const Rle& a, const Rle& b, bool crowd = false);

}  // namespace grapebench
