// PNG encoding (libpng) of 8- and 16-bit grey or RGB images, for every room that
// writes images: sensor frames (sensors/scan) and the stereo pairs of the external
// protocol (algorithms/external_estimator).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace grapebench {

// Rows of `pixels` top first; 16-bit samples big-endian, as PNG wants. colour_type:
// PNG_COLOR_TYPE_GRAY (0) or PNG_COLOR_TYPE_RGB (2). Throws InputError on failure.
std::string png_bytes(int width, int height, int bit_depth, int colour_type, const std::vector<unsigned char>& pixels);
// An 8-bit RGB image, W x H x 3.
std::string rgb_image_png(int width, int height, const std::vector<std::uint8_t>& rgb);

}  // namespace grapebench
