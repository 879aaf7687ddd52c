#include "sensors/render/cycles_render.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <future>
#include <map>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>

#include "sensors/render/row_copies.h"
#include "sensors/render/wood_atlas.h"
#include "synth/confined_program.h"
#include "synth/fnv1a.h"
#include "synth/io.h"
#include "synth/png.h"
#include "synth/read_regular_file.h"

#ifndef GRAPEBENCH_CYCLES_SCRIPT
#error "GRAPEBENCH_CYCLES_SCRIPT: the path of sensors/render/cycles_scene.py (set by CMake)"
#endif

namespace grapebench {

namespace {

using json = nlohmann::ordered_json;
json j3(const Vec3& v) { return json::array({v.x(), v.y(), v.z()}); }
json jc(const Rgb& c) { return json::array({c.r, c.g, c.b}); }
double lum(const Rgb& c) { return 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b; }

void write_file(const std::filesystem::path& path, const std::string& bytes) {
  std::ofstream f(path, std::ios::binary);
  f.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (!f) throw std::runtime_error("cycles: cannot write " + path.string());
}

template <class T>
std::vector<T> read_raw(const std::filesystem::path& path, std::size_t count) {
  std::ifstream f(path, std::ios::binary | std::ios::ate);
  if (!f) throw std::runtime_error("cycles: Blender wrote no " + path.filename().string());
  const auto size = static_cast<std::size_t>(f.tellg());
  if (size != count * sizeof(T))
    throw std::runtime_error("cycles: " + path.filename().string() + " holds " + std::to_string(size) + " bytes, want " +
                             std::to_string(count * sizeof(T)));
  std::vector<T> v(count);
  f.seekg(0);
  f.read(reinterpret_cast<char*>(v.data()), static_cast<std::streamsize>(size));
  return v;
}

std::mutex cache_mutex;
std::filesystem::path cache_folder;
int cache_scopes = 0;                 // CyclesCacheScopes alive
std::filesystem::path before_scopes;  // the folder before the first of them
std::map<std::string, std::weak_ptr<std::mutex>> key_locks;  // renders under way, by key

// Held while an entry is looked up, rendered and stored: two cases rendering the same
// image at once (a sweep of an estimator's key) render it once, the second reads it.
std::shared_ptr<std::mutex> lock_for(const std::string& key) {
  const std::lock_guard<std::mutex> lock(cache_mutex);
  std::erase_if(key_locks, [](const auto& e) { return e.second.expired(); });
  std::shared_ptr<std::mutex> m = key_locks[key].lock();
  if (!m) key_locks[key] = m = std::make_shared<std::mutex>();
  return m;
}

// Blender's binary itself, through a link in PATH where it can be resolved.
std::filesystem::path blender_binary(const std::string& blender) {
  std::error_code ec;
  const std::filesystem::path real = std::filesystem::canonical(blender, ec);
  return ec ? std::filesystem::path(blender) : real;
}

// The cache key of the render `work` holds (every file but Blender's two answers, by
// name and bytes), the script and Blender's binary: 16 hex digits.
std::string render_key(const std::filesystem::path& work, const std::string& blender) {
  std::uint64_t h = fnv1a("grapebench-cycles-cache-1");
  const auto add_file = [&](const std::filesystem::path& path) {
    std::ifstream f(path, std::ios::binary);
    if (!f) throw std::runtime_error("cycles: cannot read " + path.string() + " for the render cache's key");
    std::string chunk(1 << 20, '\0');
    while (f.read(chunk.data(), static_cast<std::streamsize>(chunk.size())) || f.gcount() > 0)
      h = fnv1a(std::string_view(chunk.data(), static_cast<std::size_t>(f.gcount())), h);
  };
  std::vector<std::filesystem::path> files;
  for (const auto& e : std::filesystem::directory_iterator(work)) {
    const std::string name = e.path().filename().string();
    if (e.is_regular_file() && name != "colour.f32" && name != "index.i32") files.push_back(e.path());
  }
  std::sort(files.begin(), files.end());
  for (const auto& f : files) {
    h = fnv1a(f.filename().string() + '\0', h);
    add_file(f);
  }
  add_file(GRAPEBENCH_CYCLES_SCRIPT);
  std::error_code ec;
  const std::filesystem::path bin = blender_binary(blender);
  const auto size = std::filesystem::file_size(bin, ec);
  const auto time = std::filesystem::last_write_time(bin, ec).time_since_epoch().count();
  h = fnv1a(bin.string() + '\0' + std::to_string(size) + '\0' + std::to_string(time), h);
  char digest[17];
  std::snprintf(digest, sizeof digest, "%016llx", static_cast<unsigned long long>(h));
  return digest;
}

// The leaves of a foliage as fans: the centre vertex of each, the triangles in order.
struct LeafFans {
  std::vector<int> centre;            // per leaf, its centre vertex
  std::vector<int> leaf_of_vertex;    // per vertex, its leaf (-1: none)
};
LeafFans leaf_fans(const Foliage& f) {
  LeafFans out;
  out.leaf_of_vertex.assign(f.vertices.size(), -1);
  std::map<int, int> index;
  for (const auto& t : f.triangles) {
    auto [it, added] = index.emplace(t[0], static_cast<int>(out.centre.size()));
    if (added) out.centre.push_back(t[0]);
    for (int k : t) out.leaf_of_vertex[static_cast<std::size_t>(k)] = it->second;
  }
  return out;
}

// The atlases depend on the scene and the appearance, not on the view, the light or
// the samples: a pair's, a rig's and a sweep's images share them. Baking and encoding
// seed 004's leaf atlases (2 x 4352^2 16-bit RGB texels at 260 leaves) took about 25 s
// an image, a cache hit included; so each is made once for the last few inputs, keyed
// by the inputs' bytes themselves (compared whole, not by a hash).
template <class Value>
class AtlasMemo {
 public:
  // The value for `inputs`: made by `make` (outside the lock) unless kept or being
  // made by another thread, whose result (or exception) is then shared.
  template <class Make>
  std::shared_ptr<const Value> get(const std::string& inputs, Make make) {
    std::unique_lock<std::mutex> lock(mutex_);
    const auto it = std::find_if(entries_.begin(), entries_.end(), [&](const Entry& e) { return e.inputs == inputs; });
    if (it != entries_.end()) {
      std::rotate(entries_.begin(), it, it + 1);  // the most recently used first
      const Future f = entries_.front().value;
      lock.unlock();
      return f.get();
    }
    std::promise<std::shared_ptr<const Value>> promise;
    entries_.insert(entries_.begin(), Entry{inputs, promise.get_future().share()});
    if (entries_.size() > kKept) entries_.pop_back();
    lock.unlock();
    try {
      auto made = std::make_shared<const Value>(make());
      promise.set_value(made);
      return made;
    } catch (...) {
      promise.set_exception(std::current_exception());
      lock.lock();
      std::erase_if(entries_, [&](const Entry& e) { return e.inputs == inputs; });
      throw;
    }
  }

 private:
  using Future = std::shared_future<std::shared_ptr<const Value>>;
  struct Entry {
    std::string inputs;
    Future value;
  };
  static constexpr std::size_t kKept = 2;  // two cases at --threads 2 may render two scenes at once
  std::mutex mutex_;
  std::vector<Entry> entries_;  // the most recently used first
};

void put_bytes(std::string& out, const void* p, std::size_t n) { out.append(static_cast<const char*>(p), n); }
void put_vec3(std::string& out, const Vec3& v) {
  const double d[3] = {v.x(), v.y(), v.z()};
  put_bytes(out, d, sizeof d);
}
std::string appearance_bytes(const AppearanceParams& a) {
  return appearance_param_table().to_json(a).dump() + '\0';
}

struct WoodAtlasFile {
  std::vector<WoodAtlasPlacement> placement;
  int width = 0, height = 0;
  std::string png;
};
struct LeafAtlasFiles {
  std::string albedo_png, transmittance_png;
};
AtlasMemo<WoodAtlasFile>& wood_memo() {
  static auto* m = new AtlasMemo<WoodAtlasFile>;  // left alive: a run's threads may outlive main
  return *m;
}
AtlasMemo<LeafAtlasFiles>& leaf_memo() {
  static auto* m = new AtlasMemo<LeafAtlasFiles>;
  return *m;
}

}  // namespace

std::string find_blender() {
  const char* env = std::getenv("GRAPEBENCH_BLENDER");
  const std::string blender = find_program(env && *env ? env : "blender");
  if (blender.empty())
    throw InputError("renderer: cycles needs Blender (Debian package `blender`, installed by scripts/setup.sh): " +
                     std::string(env && *env ? env : "blender") + " not found");
  return blender;
}

CyclesRenderResult cycles_render(const RayScene& scene, const Camera& cam, const Illumination& light,
                                 const AppearanceParams& look, const PhotoCameraParams& camera, double focal_length,
                                 const CyclesParams& cycles, std::uint64_t seed, const std::filesystem::path& work) {
  const std::string blender = find_blender();
  if (scene.background())
    throw InputError("renderer: cycles does not draw a background plate yet (the rig's plate or cloth); "
                     "use renderer: ray or opengl for this scene");
  std::filesystem::create_directories(work);
  const int W = cam.K.width, H = cam.K.height;
  json s;
  s["format"] = "grapebench-cycles-1";
  s["image"] = {{"width", W}, {"height", H}, {"samples", cycles.samples}, {"bounces", cycles.bounces},
                {"diffuse", cycles.diffuse == CyclesParams::Diffuse::Lambert ? "lambert" : "principled"},
                {"seed", static_cast<std::int64_t>(seed % 2147483647ULL)}, {"threads", cycles.threads}};
  json pose = json::array();
  const Eigen::Matrix4d P = cam.pose.matrix();
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) pose.push_back(P(r, c));
  // The sensor's width from the focal length in pixels and in metres.
  const double pitch = focal_length / cam.K.fx;
  const double focus = camera.focus_distance > 0 ? camera.focus_distance
                                                 : std::max(0.05, (cam.pose.inverse() * scene.bunch_centre()).z());
  s["camera"] = {{"pose", pose},           {"fx", cam.K.fx},
                 {"fy", cam.K.fy},         {"cx", cam.K.cx},
                 {"cy", cam.K.cy},         {"sensor_width_mm", W * pitch * 1e3},
                 {"f_number", camera.f_number}, {"focus_distance", focus}};
  s["sun"] = {{"direction", j3(light.sun_direction.normalized())},
              {"irradiance", light.sun},
              {"colour", jc(light.sun_colour)},
              {"angle_deg", light.sun_size_deg}};
  const SkyModel sky(light);
  s["sky"] = {{"kind", light.sky == Illumination::Sky::Clear ? "clear" : "overcast"},
              {"scale", sky.scale},
              {"zenith", json::array({sky.zenith[0], sky.zenith[1], sky.zenith[2]})},
              {"horizon", json::array({sky.horizon[0], sky.horizon[1], sky.horizon[2]})}};
  s["ground"] = {{"z", scene.bunch_min().z() - look.ground_below},
                 {"reflectance", jc(look.ground_reflectance)},
                 {"half_size", 200.0}};
  // Instance ids: berries 1..B, then the bunch's stems, the scene's leaves and canes;
  // id 0 (not labelled) for the row copies and the ground. id -> Part for the labels.
  std::vector<Part> part_of_id{Part::None};
  const Bunch& bunch = scene.bunch();
  json berries = json::array();
  Material bm;
  for (const Berry& b : bunch.berries) {
    bm = berry_material(look, b.colour);
    berries.push_back({{"centre", j3(b.centre)},
                       {"radius", b.radius},
                       {"albedo", jc(bm.albedo)},
                       {"transmittance", jc(bm.transmittance)},
                       {"id", static_cast<int>(part_of_id.size())}});
    part_of_id.push_back(Part::Berry);
  }
  s["berries"] = berries;
  s["berry_material"] = {{"f0", bm.specular}, {"alpha", bm.roughness}};
  if (bunch.berries.empty()) s["berry_material"] = {{"f0", look.skin_f0}, {"alpha", look.skin_roughness}};
  json cylinders = json::array();
  // The wood texture's atlas covers every drawn cylinder: the scene's own at
  // `wood_texel`, the row copies (a vine or a row away, 1.2 m and more by default) at twice it.
  std::vector<Stem> wood;
  std::vector<double> wood_texel;
  std::vector<std::size_t> wood_of;  // cylinder -> its rectangle in the atlas (npos: not drawn)
  const auto cylinder = [&](const Stem& st, const Rgb& colour, bool labelled) {
    cylinders.push_back({{"start", j3(st.start)},
                         {"end", j3(st.end)},
                         {"radius", st.radius},
                         {"albedo", jc(colour)},
                         {"id", labelled ? static_cast<int>(part_of_id.size()) : 0}});
    if (labelled) part_of_id.push_back(st.part);
    const bool drawn = st.radius > 0 && (st.end - st.start).norm() > 0;
    wood_of.push_back(drawn ? wood.size() : std::string::npos);
    if (drawn) {
      wood.push_back(st);
      wood_texel.push_back(labelled ? cycles.wood_texel : 2 * cycles.wood_texel);
    }
  };
  for (const Stem& st : bunch.stems) cylinder(st, bunch.stem_colour, true);
  const Foliage& f = scene.foliage();
  for (const Stem& st : f.canes) cylinder(st, f.colour_of(st), true);
  const RowCopies rows = row_copies(f, look, scene.bunch_min().z() - look.ground_below);
  for (const Stem& st : rows.foliage.canes) cylinder(st, f.colour_of(st), false);
  if (look.wood_texture > 0 && !wood.empty()) {
    std::string inputs = appearance_bytes(look);
    for (std::size_t i = 0; i < wood.size(); ++i) {
      put_vec3(inputs, wood[i].start), put_vec3(inputs, wood[i].end);
      put_bytes(inputs, &wood[i].radius, sizeof(double));
      put_bytes(inputs, &wood_texel[i], sizeof(double));
    }
    const auto atlas = wood_memo().get(inputs, [&] {
      const WoodAtlas a = wood_atlas(wood, wood_texel, look);
      std::vector<unsigned char> bytes(a.factor.size() * 2);
      for (int y = 0; y < a.height; ++y) {  // PNG rows run down the image, the atlas's up
        for (int x = 0; x < a.width; ++x) {
          const std::uint16_t v = a.factor[static_cast<std::size_t>(y) * a.width + x];
          const std::size_t at = 2 * (static_cast<std::size_t>(a.height - 1 - y) * a.width + x);
          bytes[at] = static_cast<unsigned char>(v >> 8);
          bytes[at + 1] = static_cast<unsigned char>(v & 0xff);
        }
      }
      return WoodAtlasFile{a.placement, a.width, a.height, png_bytes(a.width, a.height, 16, 0, bytes)};
    });
    for (std::size_t i = 0; i < cylinders.size(); ++i) {
      if (wood_of[i] == std::string::npos) continue;
      const WoodAtlasPlacement& p = atlas->placement[wood_of[i]];
      cylinders[i]["x_axis"] = j3(p.x_axis);
      // Texel centres: the point at `along` fraction t and angle a is texel
      // (x0 + 0.5 + t along, y0 + 0.5 + (a / 2 pi + 1 / 2) around).
      cylinders[i]["atlas_origin"] = json::array({p.x0 + 0.5, p.y0 + 0.5, 0.0});
      cylinders[i]["atlas_steps"] = json::array({p.along, p.around, 0});
    }
    write_file(work / "wood.png", atlas->png);
    s["wood"] = {{"png", "wood.png"}, {"width", atlas->width}, {"height", atlas->height}, {"amplitude", look.wood_texture}};
  }
  s["cylinders"] = cylinders;

  // The leaf atlas: one square cell per leaf of the scene, the leaf's own plane mapped
  // onto it, each texel the appearance model's albedo and transmittance there.
  const LeafFans fans = leaf_fans(f);
  const int n_leaves = static_cast<int>(fans.centre.size());
  const int grid = std::max(1, static_cast<int>(std::ceil(std::sqrt(static_cast<double>(n_leaves)))));
  const int T = cycles.leaf_texels, A = grid * T;
  double leaf_mean = 0;
  for (const Rgb& c : f.triangle_colour) leaf_mean += lum(c);
  leaf_mean = f.triangle_colour.empty() ? 1.0 : std::max(1e-6, leaf_mean / static_cast<double>(f.triangle_colour.size()));
  struct Frame {
    Vec3 c, e1, e2, n, tip;
    double half = 0;
    double shade = 1;
  };
  std::vector<Frame> frames(static_cast<std::size_t>(n_leaves));
  for (std::size_t t = 0; t < f.triangles.size(); ++t) {
    const auto& tri = f.triangles[t];
    const int leaf = fans.leaf_of_vertex[static_cast<std::size_t>(tri[0])];
    Frame& fr = frames[static_cast<std::size_t>(leaf)];
    if (fr.half > 0) continue;
    fr.c = f.vertices[static_cast<std::size_t>(tri[0])];
    fr.tip = f.vertices[static_cast<std::size_t>(tri[0]) + 1];
    fr.n = (f.vertices[static_cast<std::size_t>(tri[1])] - fr.c).cross(f.vertices[static_cast<std::size_t>(tri[2])] - fr.c).normalized();
    fr.e1 = (fr.tip - fr.c).normalized();
    fr.e2 = fr.n.cross(fr.e1).normalized();
    fr.shade = lum(f.triangle_colour[t]) / leaf_mean;
    fr.half = 1e-9;
  }
  for (std::size_t v = 0; v < f.vertices.size(); ++v) {
    const int leaf = fans.leaf_of_vertex[v];
    if (leaf < 0) continue;
    Frame& fr = frames[static_cast<std::size_t>(leaf)];
    fr.half = std::max(fr.half, (f.vertices[v] - fr.c).norm() * 1.02);
  }
  // uv of a scene vertex (Blender's v runs up the image).
  std::vector<std::array<double, 2>> uv(f.vertices.size(), {0.0, 0.0});
  for (std::size_t v = 0; v < f.vertices.size(); ++v) {
    const int leaf = fans.leaf_of_vertex[v];
    if (leaf < 0) continue;
    const Frame& fr = frames[static_cast<std::size_t>(leaf)];
    const Vec3 d = f.vertices[v] - fr.c;
    const double uc = d.dot(fr.e1) / (2 * fr.half) + 0.5, vc = d.dot(fr.e2) / (2 * fr.half) + 0.5;
    const int col = leaf % grid, row = leaf / grid;
    uv[v] = {(col + uc) / grid, (grid - row - 1 + vc) / grid};
  }
  if (n_leaves > 0) {
    std::string inputs = appearance_bytes(look);
    put_bytes(inputs, &T, sizeof T);
    const std::size_t sizes[3] = {f.vertices.size(), f.triangles.size(), f.triangle_colour.size()};
    put_bytes(inputs, sizes, sizeof sizes);
    for (const Vec3& v : f.vertices) put_vec3(inputs, v);
    put_bytes(inputs, f.triangles.data(), f.triangles.size() * sizeof(f.triangles[0]));
    for (const Rgb& c : f.triangle_colour) put_bytes(inputs, &c, sizeof c);
    const auto files = leaf_memo().get(inputs, [&] {
      std::vector<unsigned char> albedo(static_cast<std::size_t>(A) * A * 6, 0), trans(albedo.size(), 0);
      const auto put = [](std::vector<unsigned char>& img, std::size_t at, float value) {
        const auto q = static_cast<std::uint16_t>(std::lround(std::clamp(value, 0.0f, 1.0f) * 65535));
        img[at] = static_cast<unsigned char>(q >> 8);
        img[at + 1] = static_cast<unsigned char>(q & 0xff);
      };
      for (int leaf = 0; leaf < n_leaves; ++leaf) {
        const Frame& fr = frames[static_cast<std::size_t>(leaf)];
        const int col = leaf % grid, row = leaf / grid;
        for (int y = 0; y < T; ++y) {
          for (int x = 0; x < T; ++x) {
            const double uc = (x + 0.5) / T, vc = 1 - (y + 0.5) / T;
            const Vec3 p = fr.c + (uc - 0.5) * 2 * fr.half * fr.e1 + (vc - 0.5) * 2 * fr.half * fr.e2;
            const Material m = leaf_material(look, p, fr.c, fr.tip, fr.n, fr.shade, true);
            const std::size_t at = 6 * (static_cast<std::size_t>(row * T + y) * A + static_cast<std::size_t>(col * T + x));
            put(albedo, at, m.albedo.r), put(albedo, at + 2, m.albedo.g), put(albedo, at + 4, m.albedo.b);
            put(trans, at, m.transmittance.r), put(trans, at + 2, m.transmittance.g), put(trans, at + 4, m.transmittance.b);
          }
        }
      }
      return LeafAtlasFiles{png_bytes(A, A, 16, 2, albedo), png_bytes(A, A, 16, 2, trans)};
    });
    write_file(work / "leaf_albedo.png", files->albedo_png);
    write_file(work / "leaf_transmittance.png", files->transmittance_png);
  }
  const AppearanceParams& a = look;
  const Material upper = leaf_material(a, Vec3::Zero(), Vec3::Zero(), Vec3::UnitX(), Vec3::UnitZ(), 1.0, true);
  s["leaf_material"] = {{"albedo_png", "leaf_albedo.png"},
                        {"transmittance_png", "leaf_transmittance.png"},
                        {"back", a.leaf_back},
                        {"f0", upper.specular},
                        {"alpha", upper.roughness}};
  json leaves = json::array();
  const auto mesh = [&](const Foliage& g, std::size_t source_vertices, int id) {
    json m = {{"vertices", json::array()}, {"uv", json::array()}, {"triangles", json::array()}, {"id", id}};
    for (std::size_t v = 0; v < g.vertices.size(); ++v) {
      m["vertices"].push_back(j3(g.vertices[v]));
      const auto& t = uv[v % source_vertices];
      m["uv"].push_back(json::array({t[0], t[1]}));
    }
    for (const auto& t : g.triangles) m["triangles"].push_back(json::array({t[0], t[1], t[2]}));
    leaves.push_back(std::move(m));
  };
  if (!f.triangles.empty()) {
    mesh(f, f.vertices.size(), static_cast<int>(part_of_id.size()));
    part_of_id.push_back(Part::Leaf);
    if (!rows.foliage.triangles.empty()) mesh(rows.foliage, rows.source_vertices, 0);
  }
  s["leaves"] = leaves;
  s["outputs"] = {{"colour", "colour.f32"}, {"index", "index.i32"}};
  write_file(work / "scene.json", s.dump());
  std::filesystem::remove(work / "colour.f32");
  std::filesystem::remove(work / "index.i32");

  const std::size_t n = static_cast<std::size_t>(W) * H;
  CyclesRenderResult out;
  // Blender's answer read from `colour` and `index` (its own files or the cache's);
  // throws std::runtime_error naming what is wrong.
  const auto read_answer = [&](const std::filesystem::path& colour, const std::filesystem::path& index) {
    out.linear = read_raw<float>(colour, 3 * n);
    for (float& v : out.linear) {
      if (!std::isfinite(v) || v < 0) throw std::runtime_error("cycles: colour.f32 holds a value that is not a radiance");
      v = static_cast<float>(v * M_PI);
    }
    const std::vector<std::int32_t> ids = read_raw<std::int32_t>(index, n);
    out.part.assign(n, static_cast<std::uint8_t>(Part::None));
    for (std::size_t i = 0; i < n; ++i) {
      if (ids[i] < 0 || static_cast<std::size_t>(ids[i]) >= part_of_id.size())
        throw std::runtime_error("cycles: index.i32 holds id " + std::to_string(ids[i]) + " at pixel " + std::to_string(i) +
                                 ", outside [0, " + std::to_string(part_of_id.size() - 1) + "]");
      out.part[i] = static_cast<std::uint8_t>(part_of_id[static_cast<std::size_t>(ids[i])]);
    }
  };
  const std::filesystem::path cache = cycles_cache();
  const std::string key = cache.empty() ? std::string() : render_key(work, blender);
  const std::filesystem::path cached_colour = cache / (key + ".colour.f32"), cached_index = cache / (key + ".index.i32");
  const std::shared_ptr<std::mutex> key_lock = cache.empty() ? nullptr : lock_for(key);
  const std::unique_lock<std::mutex> rendering =
      key_lock ? std::unique_lock<std::mutex>(*key_lock) : std::unique_lock<std::mutex>();
  if (key_lock && std::filesystem::exists(cached_colour) && std::filesystem::exists(cached_index)) {
    try {
      read_answer(cached_colour, cached_index);
      out.cached = true;
      return out;
    } catch (const std::runtime_error&) {  // damaged: rendered again below, and replaced
    }
  }

  const ProgramLimits limits = cycles_program_limits(cycles, blender);
  const auto t0 = std::chrono::steady_clock::now();
  ConfinedProgram blender_run({blender, "-b", "--factory-startup", "-noaudio", "-P", GRAPEBENCH_CYCLES_SCRIPT, "--",
                               (work / "scene.json").string()},
                              work, limits);
  const auto end = blender_run.wait(t0 + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                              std::chrono::duration<double>(cycles.time_limit)));
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (end == ConfinedProgram::End::TimedOut) {
    char why[160];
    std::snprintf(why, sizeof why, "cycles: Blender stopped past its time limit of %g s (cycles.time_limit)", cycles.time_limit);
    throw std::runtime_error(why);
  }
  if (end != ConfinedProgram::End::Exited || !blender_run.failure().empty())
    throw std::runtime_error("cycles: Blender failed (" + blender_run.failure() + "): " + blender_run.error_tail());
  read_answer(work / "colour.f32", work / "index.i32");
  if (!cache.empty()) {  // only an answer that passed the checks above
    try {
      std::filesystem::create_directories(cache);
      write_file_atomic(cached_colour, read_regular_file(work / "colour.f32", 3 * n * sizeof(float)));
      write_file_atomic(cached_index, read_regular_file(work / "index.i32", n * sizeof(std::int32_t)));
    } catch (const std::exception& e) {  // the render stands; only the next run renders it again
      std::fprintf(stderr, "warning: cycles: the render cache could not keep an image: %s\n", e.what());
    }
  }
  return out;
}

void set_cycles_cache(const std::filesystem::path& folder) {
  const std::lock_guard<std::mutex> lock(cache_mutex);
  cache_folder = folder;
}

CyclesCacheScope::CyclesCacheScope(const std::filesystem::path& folder) {
  if (folder.empty()) return;
  const std::lock_guard<std::mutex> lock(cache_mutex);
  if (cache_scopes > 0 && cache_folder != folder)
    throw InputError("cycles cache: " + folder.string() + " asked for while another run in this process keeps "
                     "Cycles' images in " + cache_folder.string() +
                     "; give both the same cycles_cache, or run them one after the other");
  if (cache_scopes++ == 0) {
    before_scopes = cache_folder;
    cache_folder = folder;
  }
  joined_ = true;
}

CyclesCacheScope::~CyclesCacheScope() {
  if (!joined_) return;
  const std::lock_guard<std::mutex> lock(cache_mutex);
  if (--cache_scopes == 0) cache_folder = before_scopes;
}

std::filesystem::path cycles_cache() {
  const std::lock_guard<std::mutex> lock(cache_mutex);
  return cache_folder;
}

ProgramLimits cycles_program_limits(const CyclesParams& cycles, const std::string& blender) {
  ProgramLimits limits;
  limits.sandbox = cycles.sandbox;
  limits.cpu_seconds = cycles.time_limit * (cycles.threads + 1);
  const std::filesystem::path where = blender_binary(blender).parent_path();
  if (where.string().rfind("/usr/", 0) != 0) limits.harness_readable.push_back(where);  // a release tarball's folder
  limits.harness_readable.emplace_back(GRAPEBENCH_CYCLES_SCRIPT);  // the source tree may lie under --out
  return limits;
}

const ParamTable<CyclesParams>& cycles_param_table() {
  using P = CyclesParams;
  static const ParamTable<P> table =
      ParamTable<P>()
          .integer("samples", "count", &P::samples, 1, 4096,
                   "path samples per pixel (Debian's Blender has no denoiser: noise falls as 1/sqrt(samples))")
          .integer("bounces", "count", &P::bounces, 1, 128,
                   "cap on each kind of light-path bounce (diffuse, glossy, transmission, transparent); a "
                   "translucent pass counts as diffuse, so light crossing a berry takes 2. 12 keeps light "
                   "through leaf layers and between berries (Cycles' own default stops diffuse at 4); 1 is "
                   "about the fast renderer's one bounce, an ablation")
          .choice("diffuse", &P::diffuse, {{"principled", P::Diffuse::Principled}, {"lambert", P::Diffuse::Lambert}},
                  "the diffuse lobe of berries and leaves. principled: the Principled BSDF's (Burley 2012), "
                  "which rough surfaces make brighter towards grazing (retro-reflection); lambert: "
                  "Principled's specular over a Lambert lobe, the fast renderer's model, an ablation "
                  "(docs/seed001.md)")
          .integer("threads", "count", &P::threads, 1, 256, "Cycles' render threads")
          .real("time_limit", "s", &P::time_limit, 1, 86400, "per image, Blender's start included; past it, stopped")
          .integer("leaf_texels", "count", &P::leaf_texels, 16, 2048,
                   "texels per leaf side of the baked leaf atlas (veins 0.8 mm wide need about 0.3 mm texels)")
          .real("wood_texel", "m", &P::wood_texel, 1e-4, 0.01,
                "texel of the baked wood texture (2 mm value noise) on the scene's stems and canes; the row "
                "copies' twice it")
          .choice("sandbox", &P::sandbox, {{"bwrap", ProgramLimits::Sandbox::Bwrap}, {"none", ProgramLimits::Sandbox::None}},
                  "bwrap: Blender sees the system's folders, its script and its work folder only (as every "
                  "program the harness starts); none: where user namespaces are not available");
  return table;
}

}  // namespace grapebench
