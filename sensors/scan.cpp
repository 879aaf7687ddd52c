#include "sensors/scan.h"

#include <unistd.h>

#include <fstream>

#include <png.h>

#include <chrono>
#include <cstring>
#include <sstream>

#include "synth/io.h"
#include "synth/png.h"
#include "synth/rng.h"

namespace grapebench {

Scan scan_description(const Sensor& sensor, const Rig& rig, const BackgroundSpec& background, std::uint64_t seed) {
  Scan scan;
  scan.seed = seed;
  scan.sensor = sensor.describe();
  scan.rig = rig.describe();
  scan.background = background_param_table().to_json(background);
  return scan;
}

Scan scan_views(const RayScene& scene, const Sensor& sensor, const Rig& rig, const BackgroundSpec& background,
                std::uint64_t seed, const std::function<void(ScanView&&, std::size_t k)>& consume) {
  // The one-sensor case of scan_views_together (capture_together of one sensor is its capture).
  Scan scan = scan_description(sensor, rig, background, seed);
  const Sensor* const one = &sensor;
  scan_views_together(scene, std::span<const Sensor* const>(&one, 1), rig, background, seed,
                      [&](std::vector<ScanView>&& views, std::size_t k) {
                        consume(std::move(views.at(0)), k);
                        return true;
                      });
  return scan;
}

std::uint64_t view_seed(std::uint64_t seed, std::size_t k) { return derive_seed(seed, k); }

void scan_views_together(const RayScene& scene, std::span<const Sensor* const> sensors, const Rig& rig,
                         const BackgroundSpec& background, std::uint64_t seed,
                         const std::function<bool(std::vector<ScanView>&&, std::size_t k)>& consume) {
  if (sensors.empty()) return;
  const Sensor& first = *sensors.front();
  const auto views = rig.views(scene.bunch_centre(), scene.bunch_radius(), background);
  for (std::size_t k = 0; k < views.size(); ++k) {
    const auto t0 = std::chrono::steady_clock::now();
    std::vector<OrganisedCloud> clouds =
        first.capture_together(sensors, scene.with_background(views[k].background), views[k].pose, view_seed(seed, k));
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::vector<ScanView> out(sensors.size());
    for (std::size_t s = 0; s < sensors.size(); ++s) {
      out[s].rig = views[k];
      out[s].camera = Camera{sensors[s]->intrinsics(), views[k].pose};
      out[s].cloud = std::move(clouds.at(s));
      out[s].seconds = seconds / static_cast<double>(sensors.size());
    }
    if (!consume(std::move(out), k)) return;
  }
}

Scan scan_bunch(const RayScene& scene, const Sensor& sensor, const Rig& rig, const BackgroundSpec& background,
                std::uint64_t seed) {
  std::vector<ScanView> views;
  Scan scan = scan_views(scene, sensor, rig, background, seed,
                         [&](ScanView&& v, std::size_t) { views.push_back(std::move(v)); });
  scan.views = std::move(views);
  return scan;
}

namespace {

template <class T>
void put(std::string& s, T v) {
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  s.append(b, sizeof(T));
}

std::string json_matrix(const Eigen::Isometry3d& T) {
  std::ostringstream s;
  s.precision(17);
  s << "[";
  for (int r = 0; r < 4; ++r) {
    s << (r ? "," : "") << "[";
    for (int c = 0; c < 4; ++c) s << (c ? "," : "") << T.matrix()(r, c);
    s << "]";
  }
  s << "]";
  return s.str();
}

}  // namespace

std::string pcd_bytes(const OrganisedCloud& c, const Eigen::Isometry3d& camera_to_world) {
  const Eigen::Quaterniond q(camera_to_world.linear());
  const Vec3 t = camera_to_world.translation();
  std::ostringstream h;
  h.precision(9);
  h << "# .PCD v0.7 - grapebench organised scan view, sensor frame (x right, y down, z forward), metres\n"
    << "VERSION 0.7\nFIELDS x y z rgb normal_x normal_y normal_z label berry\n"
    << "SIZE 4 4 4 4 4 4 4 4 4\nTYPE F F F U F F F U I\nCOUNT 1 1 1 1 1 1 1 1 1\n"
    << "WIDTH " << c.width << "\nHEIGHT " << c.height << "\nVIEWPOINT " << t.x() << " " << t.y() << " " << t.z()
    << " " << q.w() << " " << q.x() << " " << q.y() << " " << q.z() << "\n"
    << "POINTS " << c.size() << "\nDATA binary\n";
  std::string s = h.str();
  s.reserve(s.size() + c.size() * 36);
  for (std::size_t i = 0; i < c.size(); ++i) {
    const float nan = NAN;
    const bool ok = c.valid[i];
    for (int k = 0; k < 3; ++k) put<float>(s, ok ? c.xyz[i][k] : nan);
    const std::uint32_t rgb =
        ok ? (std::uint32_t(c.rgb[i][0]) << 16) | (std::uint32_t(c.rgb[i][1]) << 8) | c.rgb[i][2] : 0;
    put<std::uint32_t>(s, rgb);
    for (int k = 0; k < 3; ++k) put<float>(s, ok ? c.normal[i][k] : nan);
    put<std::uint32_t>(s, ok ? c.label[i] : static_cast<std::uint32_t>(Part::None));
    put<std::int32_t>(s, ok ? c.berry[i] : -1);
  }
  return s;
}

std::string ply_points_bytes(const OrganisedCloud& c) {
  std::ostringstream h;
  h << "ply\nformat binary_little_endian 1.0\n"
    << "comment grapebench scan view, sensor frame, metres; label: 0 berry 1 pedicel 2 rachis 3 peduncle 4 background\n"
    << "element vertex " << c.valid_count() << "\n"
    << "property float x\nproperty float y\nproperty float z\n"
    << "property float nx\nproperty float ny\nproperty float nz\n"
    << "property uchar red\nproperty uchar green\nproperty uchar blue\n"
    << "property uchar label\nproperty int berry\nend_header\n";
  std::string s = h.str();
  for (std::size_t i = 0; i < c.size(); ++i) {
    if (!c.valid[i]) continue;
    for (int k = 0; k < 3; ++k) put<float>(s, c.xyz[i][k]);
    for (int k = 0; k < 3; ++k) put<float>(s, c.normal[i][k]);
    for (int k = 0; k < 3; ++k) put<std::uint8_t>(s, c.rgb[i][k]);
    put<std::uint8_t>(s, c.label[i]);
    put<std::int32_t>(s, c.berry[i]);
  }
  return s;
}

std::string depth_png_bytes(const OrganisedCloud& c) {
  std::vector<unsigned char> px(c.size() * 2, 0);
  for (std::size_t i = 0; i < c.size(); ++i) {
    if (!c.valid[i]) continue;
    const long mm = std::lround(c.xyz[i].z() * 1000.0);
    const auto v = static_cast<std::uint16_t>(std::clamp(mm, 0L, 65535L));
    px[2 * i] = static_cast<unsigned char>(v >> 8);
    px[2 * i + 1] = static_cast<unsigned char>(v & 0xFF);
  }
  return png_bytes(c.width, c.height, 16, PNG_COLOR_TYPE_GRAY, px);
}

std::string rgb_png_bytes(const OrganisedCloud& c) {
  std::vector<unsigned char> px(c.size() * 3, 0);
  for (std::size_t i = 0; i < c.size(); ++i) {
    for (int k = 0; k < 3; ++k) px[3 * i + k] = c.valid[i] ? c.rgb[i][k] : 0;
  }
  return png_bytes(c.width, c.height, 8, PNG_COLOR_TYPE_RGB, px);
}

std::string image_png_bytes(int width, int height, const std::vector<std::uint8_t>& rgb) {
  return png_bytes(width, height, 8, PNG_COLOR_TYPE_RGB, rgb);
}

std::string label_png_bytes(const OrganisedCloud& c) {
  std::vector<unsigned char> px(c.size());
  for (std::size_t i = 0; i < c.size(); ++i) px[i] = c.valid[i] ? c.label[i] : 255;
  return png_bytes(c.width, c.height, 8, PNG_COLOR_TYPE_GRAY, px);
}

namespace {

std::string merged_ply_header(std::size_t n) {
  std::ostringstream h;
  h << "ply\nformat binary_little_endian 1.0\n"
    << "comment grapebench scan, all views, world frame (z up, rachis top at the origin), metres; "
       "label: 0 berry 1 pedicel 2 rachis 3 peduncle 4 background\n"
    << "element vertex " << n << "\n"
    << "property float x\nproperty float y\nproperty float z\n"
    << "property float nx\nproperty float ny\nproperty float nz\n"
    << "property uchar red\nproperty uchar green\nproperty uchar blue\n"
    << "property uchar label\nproperty int berry\nproperty ushort view\nend_header\n";
  return h.str();
}

// View k's valid points in the world frame, as the merged PLY's binary records.
std::string merged_records(const ScanView& v, std::size_t k) {
  std::string s;
  const OrganisedCloud& c = v.cloud;
  const Eigen::Isometry3d& T = v.rig.pose;
  for (std::size_t i = 0; i < c.size(); ++i) {
    if (!c.valid[i]) continue;
    const Vec3 p = T * c.xyz[i].cast<double>();
    const Vec3 nrm = T.linear() * c.normal[i].cast<double>();
    for (int a = 0; a < 3; ++a) put<float>(s, static_cast<float>(p[a]));
    for (int a = 0; a < 3; ++a) put<float>(s, static_cast<float>(nrm[a]));
    for (int a = 0; a < 3; ++a) put<std::uint8_t>(s, c.rgb[i][a]);
    put<std::uint8_t>(s, c.label[i]);
    put<std::int32_t>(s, c.berry[i]);
    put<std::uint16_t>(s, static_cast<std::uint16_t>(k));
  }
  return s;
}

}  // namespace

std::string merged_ply_bytes(const Scan& scan) {
  std::size_t n = 0;
  for (const auto& v : scan.views) n += v.cloud.valid_count();
  std::string s = merged_ply_header(n);
  for (std::size_t k = 0; k < scan.views.size(); ++k) s += merged_records(scan.views[k], k);
  return s;
}

ScanWriter::ScanWriter(const Scan& description, const std::filesystem::path& dir, std::string stem, bool merged)
    : dir_(dir), stem_(std::move(stem)), merged_(merged) {
  std::filesystem::create_directories(dir_);
  manifest_["format"] = "grapebench-scan/1";
  manifest_["frames"] = "world: z up, bunch rachis top at the origin; camera: x right, y down, z forward";
  manifest_["seed"] = description.seed;
  manifest_["sensor"] = description.sensor;
  manifest_["rig"] = description.rig;
  manifest_["background"] = description.background;
  manifest_["views"] = nlohmann::ordered_json::array();
  if (merged_) {
    merged_body_ = dir_ / (stem_ + "_merged.ply.body." + std::to_string(::getpid()));
    std::ofstream(merged_body_, std::ios::binary | std::ios::trunc);
  }
}

ScanWriter::~ScanWriter() {
  std::error_code ec;
  if (!merged_body_.empty()) std::filesystem::remove(merged_body_, ec);
}

void ScanWriter::add(const ScanView& v) {
    const std::string base = stem_ + "_" + v.rig.name;
    write_file_atomic(dir_ / (base + ".pcd"), pcd_bytes(v.cloud, v.rig.pose));
    write_file_atomic(dir_ / (base + ".ply"), ply_points_bytes(v.cloud));
    write_file_atomic(dir_ / (base + "_depth.png"), depth_png_bytes(v.cloud));
    write_file_atomic(dir_ / (base + "_rgb.png"), rgb_png_bytes(v.cloud));
    write_file_atomic(dir_ / (base + "_label.png"), label_png_bytes(v.cloud));
    std::vector<std::string> files = {base + ".pcd", base + ".ply", base + "_depth.png", base + "_rgb.png",
                                      base + "_label.png"};
    if (!v.cloud.left_image.empty()) {
      write_file_atomic(dir_ / (base + "_left.png"), image_png_bytes(v.cloud.width, v.cloud.height, v.cloud.left_image));
      write_file_atomic(dir_ / (base + "_right.png"),
                        image_png_bytes(v.cloud.width, v.cloud.height, v.cloud.right_image));
      files.push_back(base + "_left.png");
      files.push_back(base + "_right.png");
    }
    const auto& K = v.camera.K;
    manifest_["views"].push_back(
        {{"name", v.rig.name},
         {"camera_to_world", nlohmann::ordered_json::parse(json_matrix(v.rig.pose))},
         {"turntable_angle_deg", v.rig.turntable_angle_deg},
         {"intrinsics",
          {{"width", K.width},
           {"height", K.height},
           {"fx", K.fx},
           {"fy", K.fy},
           {"cx", K.opencv_cx()},
           {"cy", K.opencv_cy()},
           {"convention", "OpenCV: the centre of pixel (u, v) is at (u, v); u = fx x / z + cx"}}},
         {"valid_points", v.cloud.valid_count()},
         {"files", files}});
  if (merged_) {
    std::ofstream body(merged_body_, std::ios::binary | std::ios::app);
    body << merged_records(v, views_);
    merged_points_ += v.cloud.valid_count();
    if (!body) throw InputError(merged_body_.string() + ": write failed (disk full?)");
  }
  ++views_;
}

void ScanWriter::finish() {
  if (merged_) {
    // Header and points into a temporary file beside the target, then renamed.
    const std::filesystem::path target = dir_ / (stem_ + "_merged.ply");
    const std::filesystem::path tmp = target.string() + ".tmp." + std::to_string(::getpid());
    {
      std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
      out << merged_ply_header(merged_points_);
      std::ifstream body(merged_body_, std::ios::binary);
      out << body.rdbuf();
      out.flush();
      if (!out) {
        std::filesystem::remove(tmp);
        throw InputError(target.string() + ": write failed (disk full?)");
      }
    }
    std::filesystem::rename(tmp, target);
    std::filesystem::remove(merged_body_);
    merged_body_.clear();
    manifest_["merged"] = stem_ + "_merged.ply";
  }
  write_file_atomic(dir_ / (stem_ + "_scan.json"), manifest_.dump(1) + "\n");
}

void write_scan(const Scan& scan, const std::filesystem::path& dir, const std::string& stem, bool merged) {
  ScanWriter writer(scan, dir, stem, merged);
  for (const auto& v : scan.views) writer.add(v);
  writer.finish();
}

}  // namespace grapebench
