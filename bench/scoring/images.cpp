#include "bench/scoring/images.h"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace grapebench {

Eigen::Vector3d linear_rgb_to_lab(const Eigen::Vector3d& rgb) {
  Eigen::Matrix3d M;
  M << 0.4124564, 0.3575761, 0.1804375, 0.2126729, 0.7151522, 0.0721750, 0.0193339, 0.1191920, 0.9503041;
  const Eigen::Vector3d xyz = M * rgb;
  const Eigen::Vector3d white(0.95047, 1.0, 1.08883);
  const auto f = [](double t) { return t > 216.0 / 24389 ? std::cbrt(t) : (24389.0 / 27 * t + 16) / 116; };
  const double fx = f(xyz.x() / white.x()), fy = f(xyz.y() / white.y()), fz = f(xyz.z() / white.z());
  return {116 * fy - 16, 500 * (fx - fy), 200 * (fy - fz)};
}

double srgb8_to_linear(std::uint8_t v) {
  const double s = v / 255.0;
  return s <= 0.04045 ? s / 12.92 : std::pow((s + 0.055) / 1.055, 2.4);
}

Eigen::Vector3d srgb8_to_lab(std::uint8_t r, std::uint8_t g, std::uint8_t b) {
  return linear_rgb_to_lab({srgb8_to_linear(r), srgb8_to_linear(g), srgb8_to_linear(b)});
}

double ciede2000(const Eigen::Vector3d& lab1, const Eigen::Vector3d& lab2) {
  const double deg = M_PI / 180;
  const double L1 = lab1[0], a1 = lab1[1], b1 = lab1[2], L2 = lab2[0], a2 = lab2[1], b2 = lab2[2];
  const double C1 = std::hypot(a1, b1), C2 = std::hypot(a2, b2), Cm = 0.5 * (C1 + C2);
  const double Cm7 = std::pow(Cm, 7);
  const double G = 0.5 * (1 - std::sqrt(Cm7 / (Cm7 + std::pow(25.0, 7))));
  const double a1p = (1 + G) * a1, a2p = (1 + G) * a2;
  const double C1p = std::hypot(a1p, b1), C2p = std::hypot(a2p, b2);
  const auto hue = [deg](double b, double a) {
    if (a == 0 && b == 0) return 0.0;
    double h = std::atan2(b, a) / deg;
    return h < 0 ? h + 360 : h;
  };
  const double h1p = hue(b1, a1p), h2p = hue(b2, a2p);
  const double dLp = L2 - L1, dCp = C2p - C1p;
  double dhp = 0;
  if (C1p * C2p != 0) {
    dhp = h2p - h1p;
    if (dhp > 180) dhp -= 360;
    if (dhp < -180) dhp += 360;
  }
  const double dHp = 2 * std::sqrt(C1p * C2p) * std::sin(0.5 * dhp * deg);
  const double Lmp = 0.5 * (L1 + L2), Cmp = 0.5 * (C1p + C2p);
  double hmp = h1p + h2p;
  if (C1p * C2p != 0) {
    if (std::abs(h1p - h2p) <= 180) hmp = 0.5 * (h1p + h2p);
    else hmp = (h1p + h2p < 360) ? 0.5 * (h1p + h2p + 360) : 0.5 * (h1p + h2p - 360);
  }
  const double T = 1 - 0.17 * std::cos((hmp - 30) * deg) + 0.24 * std::cos(2 * hmp * deg) +
                   0.32 * std::cos((3 * hmp + 6) * deg) - 0.20 * std::cos((4 * hmp - 63) * deg);
  const double dTheta = 30 * std::exp(-std::pow((hmp - 275) / 25, 2));
  const double Cmp7 = std::pow(Cmp, 7);
  const double RC = 2 * std::sqrt(Cmp7 / (Cmp7 + std::pow(25.0, 7)));
  const double SL = 1 + 0.015 * std::pow(Lmp - 50, 2) / std::sqrt(20 + std::pow(Lmp - 50, 2));
  const double SC = 1 + 0.045 * Cmp, SH = 1 + 0.015 * Cmp * T;
  const double RT = -std::sin(2 * dTheta * deg) * RC;
  const double tl = dLp / SL, tc = dCp / SC, th = dHp / SH;
  return std::sqrt(tl * tl + tc * tc + th * th + RT * tc * th);
}

double luminance_ssim(const std::vector<std::uint8_t>& a, const std::vector<std::uint8_t>& b, int width, int height) {
  const std::size_t n = static_cast<std::size_t>(width) * height;
  if (a.size() != 3 * n || b.size() != 3 * n) throw std::invalid_argument("luminance_ssim: the images are not W x H x 3");
  cv::Mat x(height, width, CV_64F), y(height, width, CV_64F);
  for (std::size_t i = 0; i < n; ++i) {
    x.at<double>(static_cast<int>(i)) = 0.2126 * a[3 * i] + 0.7152 * a[3 * i + 1] + 0.0722 * a[3 * i + 2];
    y.at<double>(static_cast<int>(i)) = 0.2126 * b[3 * i] + 0.7152 * b[3 * i + 1] + 0.0722 * b[3 * i + 2];
  }
  const double C1 = std::pow(0.01 * 255, 2), C2 = std::pow(0.03 * 255, 2);
  const auto blur = [](const cv::Mat& m) {
    cv::Mat o;
    cv::GaussianBlur(m, o, cv::Size(11, 11), 1.5, 1.5, cv::BORDER_REFLECT);
    return o;
  };
  const cv::Mat mx = blur(x), my = blur(y);
  const cv::Mat sxx = blur(x.mul(x)) - mx.mul(mx), syy = blur(y.mul(y)) - my.mul(my), sxy = blur(x.mul(y)) - mx.mul(my);
  const cv::Mat num = (2 * mx.mul(my) + C1).mul(2 * sxy + C2);
  const cv::Mat den = (mx.mul(mx) + my.mul(my) + C1).mul(sxx + syy + C2);
  cv::Mat map;
  cv::divide(num, den, map);
  return cv::mean(map)[0];
}

void PixelNoise::add(const PixelNoise& other) {
  if (pixels.size() < other.pixels.size()) {
    pixels.resize(other.pixels.size()), sum.resize(other.pixels.size()), sum_sq.resize(other.pixels.size());
  }
  for (std::size_t k = 0; k < other.pixels.size(); ++k) {
    pixels[k] += other.pixels[k];
    for (int ch = 0; ch < 3; ++ch) sum[k][ch] += other.sum[k][ch], sum_sq[k][ch] += other.sum_sq[k][ch];
  }
}

std::array<double, 3> PixelNoise::sd(std::size_t cls) const {
  std::array<double, 3> out;
  out.fill(std::numeric_limits<double>::quiet_NaN());
  if (cls >= pixels.size() || pixels[cls] == 0) return out;
  const double n = static_cast<double>(pixels[cls]);
  for (int ch = 0; ch < 3; ++ch) {
    const double mean = static_cast<double>(sum[cls][ch]) / n;
    out[ch] = std::sqrt(std::max(0.0, static_cast<double>(sum_sq[cls][ch]) / n - mean * mean));
  }
  return out;
}

PixelNoise pixel_noise(const std::vector<std::uint8_t>& rgb, const std::vector<int>& cls, int width, int height,
                       int classes) {
  const std::size_t n = static_cast<std::size_t>(width) * height;
  if (width < 1 || height < 1 || rgb.size() != 3 * n || cls.size() != n || classes < 0)
    throw std::invalid_argument("pixel_noise: the image is not W x H x 3 or the classes not W x H");
  for (const int c : cls)
    if (c < -1 || c >= classes) throw std::invalid_argument("pixel_noise: a class outside [-1, classes)");
  PixelNoise out;
  out.pixels.assign(static_cast<std::size_t>(classes), 0);
  out.sum.assign(static_cast<std::size_t>(classes), {0, 0, 0});
  out.sum_sq = out.sum;
  const cv::Mat image(height, width, CV_8UC3, const_cast<std::uint8_t*>(rgb.data()));
  cv::Mat median;
  cv::medianBlur(image, median, 3);
  for (int y = 1; y + 1 < height; ++y)
    for (int x = 1; x + 1 < width; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * width + x;
      const int c = cls[i];
      if (c < 0) continue;
      bool inner = true;
      for (int dy = -1; dy <= 1 && inner; ++dy)
        for (int dx = -1; dx <= 1; ++dx)
          if (cls[i + static_cast<std::ptrdiff_t>(dy) * width + dx] != c) inner = false;
      if (!inner) continue;
      const auto k = static_cast<std::size_t>(c);
      out.pixels[k] += 1;
      for (int ch = 0; ch < 3; ++ch) {
        const long long r = static_cast<long long>(rgb[3 * i + ch]) - median.data[3 * i + ch];
        out.sum[k][ch] += r, out.sum_sq[k][ch] += r * r;
      }
    }
  return out;
}

}  // namespace grapebench
