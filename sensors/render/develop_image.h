// A colour camera's image chain after the optics: vignetting, exposure (fixed or
// metered), photon shot noise and read noise in electrons, the ADC, a Bayer mosaic
// and its demosaicing (OpenCV), the sRGB response and JPEG. The renderer supplies the
// linear irradiance image (already anti-aliased over the pixel and defocused at the
// f-number, which it samples). Scene section `camera:` of a colour sensor.
#pragma once

#include <cstdint>
#include <vector>

#include "sensors/camera.h"
#include "synth/param_table.h"

namespace grapebench {

struct PhotoCameraParams {
  // Done by the renderer: one ray at each pixel's centre and, where what is seen
  // changes, samples^2 more stratified over the pixel (a box filter); a thin lens at
  // f_number (0: pinhole) focused at focus_distance (0: the bunch's centre).
  int samples = 2;               // per pixel side at edges, [1, 8]
  int sky_samples = 1;           // sky rays a surface sample casts per face (ray renderer), [1, 64]
  int sky_filter = 3;            // passes of the sky light's edge-aware filter (ray renderer): 1 is 5 x 5 px,
                                 // 3 (29 x 29) agrees with Cycles on both seeds (docs/sensors.md item 5), [1, 4]
  int sky_stride = 2;            // px between pixels that cast sky rays, per axis (ray renderer): 2 casts them
                                 // from one pixel in 2 x 2, filters there and upsamples; 1 every pixel (the
                                 // default until 2026-12-07: docs/sensors.md item 8), [1, 2]
  double f_number = 4.0;         // [0 or 1, 32]; 0 = pinhole
  double focus_distance = 0;     // m, [0, 100]; 0 = on the bunch
  enum class Exposure { Auto, Fixed };
  Exposure exposure = Exposure::Auto;
  double exposure_gain = 1.0;    // fixed: full scale = this many times the sun's irradiance on white, [1e-3, 1e3]
  double auto_target = 0.18;     // auto: mean linear luminance after exposure, [0.01, 0.9]
  double full_well = 10000;      // electrons at full scale, [100, 1e6]
  double read_noise = 5;         // electrons rms, [0, 1000]
  int adc_bits = 12;             // [8, 16]
  enum class Bayer { None, Rggb };
  Bayer bayer = Bayer::Rggb;
  enum class Demosaic { Bilinear, EdgeAware };
  Demosaic demosaic = Demosaic::EdgeAware;
  double vignetting = 1.0;       // strength of the cos^4 law, [0, 1]
  int jpeg_quality = 0;          // 0: none (lossless), else [1, 100]
};
const ParamTable<PhotoCameraParams>& photo_camera_param_table();

struct DevelopResult {
  std::vector<std::uint8_t> rgb;  // H x W x 3, sRGB, top row first
  double gain = 0;                // the exposure applied: full scale over irradiance
  double saturated_fraction = 0;  // pixels with a channel at full scale
  std::vector<std::uint8_t> jpeg;  // jpeg_quality > 0: the encoded file whose decoding `rgb` is
};

// `linear`: H x W x 3 irradiance, relative (1 = white paper under the full sun); every
// draw from `seed` and the pixel index. `gain` > 0 overrides the exposure (the right
// image of a pair takes the left's, as a synchronised pair does).
DevelopResult develop_image(const std::vector<float>& linear, const Intrinsics& K, const PhotoCameraParams& p,
                            std::uint64_t seed, double gain = 0);

// sRGB's transfer function (IEC 61966-2-1) of a linear value in [0, 1].
double srgb_encode(double linear);

}  // namespace grapebench
