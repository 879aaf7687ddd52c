// The fast renderer (ray) against the physically based reference (Blender's Cycles) on
// a fixed validation set: 3 varieties x 3 lights (seed 001's sunny front, sunny
// overshadow, overcast) x 3 distances (350-1100 mm, cycled), the vine row's foliage
// around each cluster with its trellis (two wire pairs, a post every 5 vines): 27 views
// of seed 001's left camera. Both images go through the same camera chain with the
// same exposure and noise. Per view: the label agreement of Cycles' object-index pass
// with the exact labels (IoU per class), the CIEDE2000 difference of each class's mean
// colour, luminance SSIM, and the luma gradient across berry boundaries (its 10th, 50th
// and 90th percentiles for each renderer, and the two distributions' Kolmogorov-Smirnov
// distance); a CSV, the
// views as PNGs (opengl | ray | cycles) and a summary table.
//   build/bench/grapebench_render_agreement --out build/agreement [--scale 1] [--samples 64] [--views 27]
#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "bench/scoring/images.h"
#include "sensors/ideal.h"
#include "sensors/render/cycles_render.h"
#include "sensors/render/ray_render.h"
#include "sensors/stereo_rgb.h"
#include "synth/foliage.h"
#include "synth/generate.h"
#include "synth/png.h"
#include "synth/rng.h"

using namespace grapebench;

namespace {

struct View {
  std::string variety;
  StereoRgbParams::Light light;
  std::string light_name;
  double distance;
  std::uint64_t seed;
};

std::vector<View> validation_set() {
  const std::vector<std::string> varieties = {"summer-black", "table-red", "green-table"};
  const std::vector<std::pair<StereoRgbParams::Light, std::string>> lights = {
      {StereoRgbParams::Light::Front, "front"}, {StereoRgbParams::Light::Overshadow, "overshadow"},
      {StereoRgbParams::Light::Overcast, "overcast"}};
  const double distances[] = {0.35, 0.725, 1.1};
  std::vector<View> views;
  std::uint64_t seed = 1;
  for (const auto& v : varieties)
    for (const auto& [l, name] : lights)
      for (int d = 0; d < 3; ++d) views.push_back({v, l, name, distances[(d + views.size() / 3) % 3], seed++});
  return views;
}

// Classes scored: berry, stem (pedicel, rachis, peduncle), foliage (leaf, cane), and
// the rest (row copies, ground, sky) where the exact scene has no return.
int class_of(std::uint8_t part) {
  switch (static_cast<Part>(part)) {
    case Part::Berry: return 0;
    case Part::Pedicel: case Part::Rachis: case Part::Peduncle: return 1;
    case Part::Leaf: case Part::Cane: return 2;
    default: return 3;
  }
}
const char* kClass[] = {"berry", "stem", "foliage", "background"};

// The luma gradient magnitude (Sobel, 8-bit units) at every berry pixel on a berry's
// boundary (a 4-neighbour not a berry), sorted: its distribution, not only its median
// (issue 38, item 5: "the distribution of gradient magnitude across berry boundaries").
std::vector<double> boundary_gradients(const std::vector<std::uint8_t>& rgb, const std::vector<std::uint8_t>& label, int W, int H) {
  cv::Mat y(H, W, CV_32F);
  for (int i = 0; i < W * H; ++i) y.at<float>(i) = 0.2126f * rgb[3 * i] + 0.7152f * rgb[3 * i + 1] + 0.0722f * rgb[3 * i + 2];
  cv::Mat gx, gy;
  cv::Sobel(y, gx, CV_32F, 1, 0);
  cv::Sobel(y, gy, CV_32F, 0, 1);
  std::vector<double> g;
  const auto berry = [&](int u, int v) { return label[static_cast<std::size_t>(v) * W + u] == static_cast<std::uint8_t>(Part::Berry); };
  for (int v = 1; v + 1 < H; ++v)
    for (int u = 1; u + 1 < W; ++u)
      if (berry(u, v) && (!berry(u - 1, v) || !berry(u + 1, v) || !berry(u, v - 1) || !berry(u, v + 1)))
        g.push_back(std::hypot(gx.at<float>(v, u), gy.at<float>(v, u)));
  std::sort(g.begin(), g.end());
  return g;
}

// The q-quantile of a sorted sample (nearest rank); NaN when empty.
double quantile(const std::vector<double>& sorted, double q) {
  if (sorted.empty()) return std::nan("");
  return sorted[std::min(sorted.size() - 1, static_cast<std::size_t>(q * static_cast<double>(sorted.size())))];
}

// Two-sample Kolmogorov-Smirnov distance of two sorted samples: the largest gap between
// their empirical distribution functions, 0 (the same) to 1 (disjoint); NaN when either
// is empty.
double ks_distance(const std::vector<double>& a, const std::vector<double>& b) {
  if (a.empty() || b.empty()) return std::nan("");
  double d = 0;
  std::size_t i = 0, j = 0;
  while (i < a.size() && j < b.size()) {
    const double x = std::min(a[i], b[j]);
    while (i < a.size() && a[i] <= x) ++i;
    while (j < b.size() && b[j] <= x) ++j;
    d = std::max(d, std::abs(static_cast<double>(i) / a.size() - static_cast<double>(j) / b.size()));
  }
  return d;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"The ray renderer against Cycles on the validation set"};
  std::string out = "agreement";
  int scale = 1, samples = 64, count = 27, threads = 2;
  app.add_option("--out", out, "output folder");
  app.add_option("--scale", scale, "image size divisor of 800 x 600 (4: 200 x 150)")->check(CLI::Range(1, 16));
  app.add_option("--samples", samples, "Cycles samples per pixel")->check(CLI::Range(1, 4096));
  app.add_option("--views", count, "the first N views of the 27")->check(CLI::Range(1, 27));
  app.add_option("--threads", threads, "Cycles threads")->check(CLI::Range(1, 256));
  bool trellis = true;
  app.add_option("--trellis", trellis, "the wires and posts in the views (0: the set before them)");
  std::vector<int> only;
  app.add_option("--only", only, "these views (0-26) instead")->check(CLI::Range(0, 26));
  std::vector<int> sky_filters = {PhotoCameraParams{}.sky_filter};
  app.add_option("--sky-filter", sky_filters,
                 "ray's camera: sky_filter, one or more (each against the same Cycles image; the panels show the first)")
      ->check(CLI::Range(1, 4));
  std::vector<int> sky_strides = {PhotoCameraParams{}.sky_stride};
  app.add_option("--sky-stride", sky_strides, "ray's camera: sky_stride, one or more (each with every --sky-filter)")
      ->check(CLI::Range(1, 2));
  CLI11_PARSE(app, argc, argv);
  std::vector<std::pair<int, int>> variants;  // (sky_filter, sky_stride), the first shown in the panels
  for (const int sky_filter : sky_filters)
    for (const int sky_stride : sky_strides) variants.emplace_back(sky_filter, sky_stride);
  try {
    std::filesystem::create_directories(out);
    std::ofstream csv(std::filesystem::path(out) / "agreement.csv");
    csv << "view,sky_filter,sky_stride,variety,light,distance_m,iou_berry,iou_stem,iou_foliage,de_berry,de_stem,de_foliage,de_background,"
           "ssim,grad_ray,grad_cycles,ray_s,cycles_s,grad_ray_p10,grad_ray_p90,grad_cycles_p10,grad_cycles_p90,grad_ks\n";
    const std::vector<View> set = validation_set();
    std::vector<std::size_t> chosen;
    for (int k = 0; k < count; ++k) chosen.push_back(static_cast<std::size_t>(k));
    if (!only.empty()) chosen.assign(only.begin(), only.end());
    std::map<std::string, std::vector<double>> all;
    for (const std::size_t k : chosen) {
      const View& v = set[k];
      const Bunch bunch = generate_bunch(preset(v.variety), v.seed);
      FoliageParams fp;
      fp.wire_pairs = trellis ? 2 : 0;  // the trellis (issue 38, item 6): two wire pairs, posts every 5 vines
      const Foliage foliage = generate_foliage(fp, bunch, derive_seed(v.seed, 1));
      const RayScene scene(bunch, std::nullopt, foliage);
      StereoRgbParams p;
      p.width = 800 / scale;
      p.height = 600 / scale;
      p.pixel_pitch_um *= scale;
      p.light = v.light;
      p.renderer = StereoRgbParams::Renderer::Ray;
      p.appearance.post_every = trellis ? 5 : 0;
      const StereoRgb rig(p);
      const Vec3 c = scene.bunch_centre();
      const Camera cam{rig.intrinsics(), look_at(c - Vec3(0, v.distance, 0), c)};
      const Illumination light = stereo_rgb_illumination(p, cam.pose);
      const double f = p.focal_length_mm * 1e-3;
      const OrganisedCloud exact = capture_exact(scene, cam);
      CyclesParams cp;
      cp.samples = samples;
      cp.threads = threads;
      const std::string name = "view" + std::to_string(k);
      const CyclesRenderResult cyc =
          cycles_render(scene, cam, light, p.appearance, p.camera, f, cp, 77, std::filesystem::path(out) / "work" / name);
      const int W = cam.K.width, H = cam.K.height;
      const std::size_t n = static_cast<std::size_t>(W) * H;
      // Label agreement per class (Cycles' index pass: the same for every sky_filter).
      double iou[3];
      for (int cls = 0; cls < 3; ++cls) {
        std::size_t both = 0, either = 0;
        for (std::size_t i = 0; i < n; ++i) {
          const bool a = exact.valid[i] && class_of(exact.label[i]) == cls, b = class_of(cyc.part[i]) == cls;
          both += a && b;
          either += a || b;
        }
        iou[cls] = either ? static_cast<double>(both) / either : std::nan("");
      }
      std::vector<std::uint8_t> label(n);
      for (std::size_t i = 0; i < n; ++i) label[i] = exact.valid[i] ? exact.label[i] : 255;
      std::vector<std::uint8_t> shown, shown_cycles;  // the first variant's images (sky_filter, sky_stride), for the panels
      for (const auto& [sky_filter, sky_stride] : variants) {
        p.camera.sky_filter = sky_filter;
        p.camera.sky_stride = sky_stride;
        const auto t0 = std::chrono::steady_clock::now();
        const RayRenderResult ray = ray_render(scene, cam, light, p.appearance, p.camera, f, 77);
        const double ray_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        const DevelopResult dr = develop_image(ray.linear, cam.K, p.camera, 5);
        if (shown.empty()) shown = dr.rgb;
        const DevelopResult dc = develop_image(cyc.linear, cam.K, p.camera, 5, dr.gain);
        if (shown_cycles.empty()) shown_cycles = dc.rgb;
        // Class mean colours (8-bit sRGB decoded to linear, averaged, to L*a*b*).
        double de[4];
        for (int cls = 0; cls < 4; ++cls) {
          Eigen::Vector3d sr = Eigen::Vector3d::Zero(), sc = Eigen::Vector3d::Zero();
          std::size_t m = 0;
          for (std::size_t i = 0; i < n; ++i) {
            if ((exact.valid[i] ? class_of(exact.label[i]) : 3) != cls) continue;
            for (int ch = 0; ch < 3; ++ch) sr[ch] += srgb8_to_linear(dr.rgb[3 * i + ch]), sc[ch] += srgb8_to_linear(dc.rgb[3 * i + ch]);
            ++m;
          }
          de[cls] = m >= 20 ? ciede2000(linear_rgb_to_lab(sr / m), linear_rgb_to_lab(sc / m)) : std::nan("");
        }
        const double ssim = luminance_ssim(dr.rgb, dc.rgb, W, H);
        const std::vector<double> gray = boundary_gradients(dr.rgb, label, W, H), gcyc = boundary_gradients(dc.rgb, label, W, H);
        const double r10 = quantile(gray, 0.1), gr = quantile(gray, 0.5), r90 = quantile(gray, 0.9);
        const double c10 = quantile(gcyc, 0.1), gc = quantile(gcyc, 0.5), c90 = quantile(gcyc, 0.9);
        const double ks = ks_distance(gray, gcyc);
        char line[640];
        std::snprintf(line, sizeof line,
                      "%zu,%d,%d,%s,%s,%.3f,%.4f,%.4f,%.4f,%.2f,%.2f,%.2f,%.2f,%.4f,%.1f,%.1f,%.2f,%.2f,%.1f,%.1f,%.1f,%.1f,%.4f\n", k,
                      sky_filter, sky_stride, v.variety.c_str(), v.light_name.c_str(), v.distance, iou[0], iou[1], iou[2], de[0], de[1], de[2], de[3],
                      ssim, gr, gc, ray_s, cyc.seconds, r10, r90, c10, c90, ks);
        csv << line;
        std::fputs(line, stdout);
        std::fflush(stdout);
        std::string prefix;
        if (sky_filters.size() > 1) prefix += "sky_filter " + std::to_string(sky_filter) + ": ";
        if (sky_strides.size() > 1) prefix += "sky_stride " + std::to_string(sky_stride) + ": ";
        const auto keep = [&](const std::string& key, double x) {
          if (std::isfinite(x)) all[prefix + key].push_back(x);
        };
        for (int cls = 0; cls < 3; ++cls) keep(std::string("iou_") + kClass[cls], iou[cls]);
        for (int cls = 0; cls < 4; ++cls) keep(std::string("de_") + kClass[cls], de[cls]);
        keep("ssim", ssim);
        keep("grad_ratio", gr / gc);
        keep("grad_p10_ratio", r10 / c10);
        keep("grad_p90_ratio", r90 / c90);
        keep("grad_ks", ks);
        keep("ray_s", ray_s);
        keep("cycles_s", cyc.seconds);
      }
      p.camera.sky_filter = variants.front().first;
      p.camera.sky_stride = variants.front().second;
      // The view side by side: opengl (the images every figure so far was measured
      // on, same light) | ray | cycles.
      StereoRgbParams gl = p;
      gl.renderer = StereoRgbParams::Renderer::OpenGl;
      const std::vector<std::uint8_t> dg = StereoRgb(gl).capture(scene, cam.pose, 5).left_image;
      std::vector<std::uint8_t> three(3 * n * 3);
      for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x)
          for (int ch = 0; ch < 3; ++ch) {
            const std::size_t i = 3 * (static_cast<std::size_t>(y) * W + x) + ch;
            three[3 * (static_cast<std::size_t>(y) * 3 * W + x) + ch] = dg[i];
            three[3 * (static_cast<std::size_t>(y) * 3 * W + W + x) + ch] = shown[i];
            three[3 * (static_cast<std::size_t>(y) * 3 * W + 2 * W + x) + ch] = shown_cycles[i];
          }
      std::ofstream(std::filesystem::path(out) / (name + ".png"), std::ios::binary) << rgb_image_png(3 * W, H, three);
      // And as JPEG (quality 88) for the docs.
      cv::Mat rgb(H, 3 * W, CV_8UC3, three.data()), bgr;
      cv::cvtColor(rgb, bgr, cv::COLOR_RGB2BGR);
      cv::imwrite((std::filesystem::path(out) / (name + ".jpg")).string(), bgr, {cv::IMWRITE_JPEG_QUALITY, 88});
    }
    std::printf("\n| figure | mean | worst | views |\n|---|---|---|---|\n");
    for (const auto& [key, xs] : all) {
      double mean = 0;
      for (double x : xs) mean += x;
      mean /= xs.size();
      const std::size_t colon = key.rfind(": ");  // after "sky_filter N: " and "sky_stride N: " prefixes
      const std::string base = colon == std::string::npos ? key : key.substr(colon + 2);
      const bool higher_better = base.rfind("iou", 0) == 0 || base == "ssim";
      const double worst = higher_better ? *std::min_element(xs.begin(), xs.end()) : *std::max_element(xs.begin(), xs.end());
      std::printf("| %s | %.4g | %.4g | %zu |\n", key.c_str(), mean, worst, xs.size());
    }
    return 0;
  } catch (const InputError& e) {
    std::fprintf(stderr, "render_agreement: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "render_agreement: %s\n", e.what());
    return 1;
  }
}
