#include "sensors/render/develop_image.h"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <cmath>

#include "synth/rng.h"

namespace grapebench {

double srgb_encode(double v) {
  v = std::clamp(v, 0.0, 1.0);
  return v <= 0.0031308 ? 12.92 * v : 1.055 * std::pow(v, 1 / 2.4) - 0.055;
}

DevelopResult develop_image(const std::vector<float>& linear, const Intrinsics& K, const PhotoCameraParams& p,
                            std::uint64_t seed, double gain) {
  const int W = K.width, H = K.height;
  const std::size_t n = static_cast<std::size_t>(W) * H;
  if (linear.size() != 3 * n) throw InputError("develop_image: the image is not width x height x 3");
  // Vignetting: the cos^4 law of the field angle (natural falloff of a thin lens).
  std::vector<float> v(linear);
  if (p.vignetting > 0) {
    for (int y = 0; y < H; ++y)
      for (int x = 0; x < W; ++x) {
        const double dx = (x + 0.5 - K.cx) / K.fx, dy = (y + 0.5 - K.cy) / K.fy;
        const double c2 = 1 / (1 + dx * dx + dy * dy);
        const double k = 1 - p.vignetting * (1 - c2 * c2);
        for (int c = 0; c < 3; ++c) v[3 * (static_cast<std::size_t>(y) * W + x) + c] *= static_cast<float>(k);
      }
  }
  DevelopResult out;
  if (gain <= 0) {
    if (p.exposure == PhotoCameraParams::Exposure::Fixed) {
      gain = p.exposure_gain;
    } else {
      // Average metering: the mean luminance (Rec. 709 weights) to the target, as
      // ISO 12232's standard output sensitivity puts 18 % grey at 118 of 255 in sRGB.
      double sum = 0;
      for (std::size_t i = 0; i < n; ++i) sum += 0.2126 * v[3 * i] + 0.7152 * v[3 * i + 1] + 0.0722 * v[3 * i + 2];
      const double mean = sum / static_cast<double>(n);
      gain = mean > 1e-12 ? p.auto_target / mean : 1.0;
    }
  }
  out.gain = gain;
  // Electrons per channel sample: shot noise (Poisson, as a normal of variance equal
  // to the mean: every pixel of interest collects hundreds), read noise, clipping at
  // the full well, the ADC's levels.
  const double levels = std::ldexp(1.0, p.adc_bits) - 1;
  const bool mosaic = p.bayer == PhotoCameraParams::Bayer::Rggb;
  cv::Mat raw(H, W, mosaic ? CV_16UC1 : CV_16UC3);
  std::size_t saturated = 0;
  const auto sample = [&](std::size_t pixel, int c) {
    const double e = std::max(0.0, gain * v[3 * pixel + c]) * p.full_well;
    const double noisy = e + std::sqrt(e) * hashed_normal_tabulated(seed, 3 * pixel + c) +
                         p.read_noise * hashed_normal_tabulated(derive_seed(seed, 1), 3 * pixel + c);
    const double level = std::clamp(noisy / p.full_well, 0.0, 1.0) * levels;
    if (noisy >= p.full_well) ++saturated;
    return static_cast<std::uint16_t>(std::lround(level));
  };
  for (int y = 0; y < H; ++y) {
    for (int x = 0; x < W; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * W + x;
      if (mosaic) {
        // R G / G B from the top-left pixel.
        const int c = (y % 2 == 0) ? (x % 2 == 0 ? 0 : 1) : (x % 2 == 0 ? 1 : 2);
        raw.at<std::uint16_t>(y, x) = sample(i, c);
      } else {
        auto& px = raw.at<cv::Vec<std::uint16_t, 3>>(y, x);
        for (int c = 0; c < 3; ++c) px[c] = sample(i, c);
      }
    }
  }
  out.saturated_fraction = static_cast<double>(saturated) / static_cast<double>(n * (mosaic ? 1 : 3));
  cv::Mat rgb16;
  if (mosaic) {
    // OpenCV names a pattern by the second row's second and third pixels: an RGGB
    // sensor is its BayerBG (tests/sensors/render/develop_image_test.cpp checks it).
    cv::demosaicing(raw, rgb16,
                    p.demosaic == PhotoCameraParams::Demosaic::EdgeAware ? cv::COLOR_BayerBG2RGB_EA : cv::COLOR_BayerBG2RGB);
  } else {
    rgb16 = raw;
  }
  // sRGB response through a table over the ADC's levels.
  std::vector<std::uint8_t> lut(static_cast<std::size_t>(levels) + 1);
  for (std::size_t l = 0; l < lut.size(); ++l) lut[l] = static_cast<std::uint8_t>(std::lround(255 * srgb_encode(l / levels)));
  out.rgb.resize(3 * n);
  for (int y = 0; y < H; ++y) {
    const auto* row = rgb16.ptr<cv::Vec<std::uint16_t, 3>>(y);
    for (int x = 0; x < W; ++x)
      for (int c = 0; c < 3; ++c)
        out.rgb[3 * (static_cast<std::size_t>(y) * W + x) + c] = lut[std::min<std::size_t>(row[x][c], lut.size() - 1)];
  }
  if (p.jpeg_quality > 0) {
    // OpenCV's codecs take BGR.
    cv::Mat img(H, W, CV_8UC3, out.rgb.data()), bgr, back;
    cv::cvtColor(img, bgr, cv::COLOR_RGB2BGR);
    std::vector<std::uint8_t> bytes;
    if (!cv::imencode(".jpg", bgr, bytes, {cv::IMWRITE_JPEG_QUALITY, p.jpeg_quality}))
      throw InputError("develop_image: JPEG encoding failed");
    back = cv::imdecode(bytes, cv::IMREAD_COLOR);
    cv::Mat rgb;
    cv::cvtColor(back, rgb, cv::COLOR_BGR2RGB);
    std::copy(rgb.data, rgb.data + 3 * n, out.rgb.begin());
    out.jpeg = std::move(bytes);
  }
  return out;
}

const ParamTable<PhotoCameraParams>& photo_camera_param_table() {
  using P = PhotoCameraParams;
  static const ParamTable<P> table =
      ParamTable<P>()
          .integer("samples", "count", &P::samples, 1, 8,
                   "anti-aliasing: where what a pixel sees changes, samples^2 more rays stratified over it")
          .integer("sky_samples", "count", &P::sky_samples, 1, 64,
                   "`ray` renderer: sky rays a pixel's surface casts per face before the sky filter; more "
                   "lowers the filtered light's blotches, which differ between a pair's two images (docs/seed004.md)")
          .integer("sky_filter", "passes", &P::sky_filter, 1, 4,
                   "`ray` renderer: passes of the sky light's edge-aware filter; 1 is 5 x 5 pixels, each further "
                   "pass doubles the step (a-trous, Dammertz et al. 2010: 2 spans 13 x 13, 3 spans 29 x 29), lowering "
                   "the one sky ray's blotches without more rays. 3, the default: where both seed 001's berries (against "
                   "Cycles at 64 samples) and seed 004's AUCs (at 256) agree with Cycles (docs/sensors.md, item 5)")
          .integer("sky_stride", "px", &P::sky_stride, 1, 2,
                   "`ray` renderer: pixels between those that cast sky rays, along each axis. 1: every pixel; 2: one "
                   "in 2 x 2, the filter's passes run on that grid (steps 2, 4, 8 px) and every other pixel takes "
                   "the light of the grid's nearest compatible pixels (a joint bilateral upsampling on part, depth "
                   "and normal, as the filter weighs; Kopf et al. 2007); a pixel with none casts its own. 2, the "
                   "default since 2026-12-07: 0.63-0.81 of 1's time, each of item 5's figures against Cycles inside "
                   "its target where 1's is, and seed 004's saliency AUC nearer (docs/sensors.md, items 5 and 8)")
          .real("f_number", "-", &P::f_number, 0, 32,
                "aperture of the thin lens, 0: pinhole (assumed f/4 for a 6 mm machine-vision lens)")
          .validate([](const P& p, const ConfigNode& node) {
            if (p.f_number > 0 && p.f_number < 1) node.fail("f_number", "0 (pinhole) or in [1, 32]");
          })
          .real("focus_distance", "m", &P::focus_distance, 0, 100, "where the lens focuses; 0: the bunch's centre")
          .choice("exposure", &P::exposure, {{"auto", P::Exposure::Auto}, {"fixed", P::Exposure::Fixed}},
                  "auto: average metering to auto_target (both cameras of a pair take the left's); fixed: exposure_gain")
          .real("exposure_gain", "-", &P::exposure_gain, 1e-3, 1e3,
                "fixed: full scale over the irradiance (1: white paper in full sun saturates)")
          .when("exposure: fixed", [](const P& p) { return p.exposure == P::Exposure::Fixed; })
          .real("auto_target", "-", &P::auto_target, 0.01, 0.9,
                "auto: mean linear luminance after exposure (ISO 12232 SOS: 18 % grey at 118/255)")
          .when("exposure: auto", [](const P& p) { return p.exposure == P::Exposure::Auto; })
          .real("full_well", "e-", &P::full_well, 100, 1e6,
                "electrons at full scale: photon shot noise (assumed 10 ke-, a 6 um CMOS pixel)")
          .real("read_noise", "e-", &P::read_noise, 0, 1000, "read noise rms (assumed 5 e-, typical CMOS)")
          .integer("adc_bits", "bits", &P::adc_bits, 8, 16, "ADC resolution (12 bits: machine-vision cameras)")
          .choice("bayer", &P::bayer, {{"none", P::Bayer::None}, {"rggb", P::Bayer::Rggb}},
                  "colour filter array: one channel per pixel, demosaiced")
          .choice("demosaic", &P::demosaic, {{"bilinear", P::Demosaic::Bilinear}, {"edge_aware", P::Demosaic::EdgeAware}},
                  "OpenCV's demosaicing (edge-aware: its _EA variant)")
          .when("bayer: rggb", [](const P& p) { return p.bayer == P::Bayer::Rggb; })
          .real("vignetting", "-", &P::vignetting, 0, 1, "strength of the cos^4 falloff (1: the natural law of a thin lens)")
          .integer("jpeg_quality", "-", &P::jpeg_quality, 0, 100, "JPEG quality of the stored image; 0: lossless");
  return table;
}

}  // namespace grapebench
