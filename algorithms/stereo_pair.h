// A rectified colour stereo pair as seed 001's system takes it (Luo et al. 2016,
// Sect. 2.2.1: calibrated and rectified, so a point's rows agree in both images).
#pragma once

#include <cstdint>
#include <vector>

namespace grapebench {

// 8-bit RGB image, H x W x 3, row-major, top row first.
struct RgbImage {
  int width = 0, height = 0;  // pixels
  std::vector<std::uint8_t> data;
  const std::uint8_t* pixel(int x, int y) const { return data.data() + (static_cast<std::size_t>(y) * width + x) * 3; }
};

// Pixel coordinates follow OpenCV: pixel (x, y) has its centre at (x, y).
struct StereoPair {
  RgbImage left, right;
  double fx = 0, fy = 0;  // pixels, both cameras
  double cx = 0, cy = 0;  // principal point, pixels, both cameras (rectified)
  double baseline = 0;    // m, left to right camera along +x
};

}  // namespace grapebench
