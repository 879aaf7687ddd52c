#include "bench/dataset_run.h"

#include <sys/resource.h>
#include <tbb/global_control.h>
#include <tbb/info.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <map>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "bench/build_info.h"
#include "bench/coco_rle.h"
#include "bench/protocols/stereo_pair.h"
#include "sensors/render/ray_render.h"
#include "sensors/scan.h"
#include "sensors/stereo_rgb.h"
#include "synth/generate.h"
#include "synth/ground_truth.h"
#include "synth/io.h"
#include "synth/rng.h"
#include "synth/vine_row.h"

namespace grapebench {

int dataset_split(std::uint64_t bunch_seed, const DatasetParams& p) {
  const double u = static_cast<double>(derive_seed(bunch_seed, 0x5b17) >> 11) * 0x1.0p-53;
  return u < p.train ? 0 : u < p.train + p.val ? 1 : 2;
}

namespace {

using Json = nlohmann::ordered_json;
enum Category : int { kBunch = 1, kBerry = 2, kStalk = 3, kLeaf = 4, kCane = 5 };

// One bunch of a case, where it sits in the scene's (possibly merged) bunch.
struct CaseBunch {
  Bunch original;  // as generated (a vine row's bunch before it is hung on the cordon)
  Vec3 shift = Vec3::Zero();  // original -> scene: a translation (synth/vine_row.cpp)
  int berry0 = 0, stem0 = 0;  // its first berry and stem in the scene's bunch
  double branch_z = 0;        // world z of its first branch (the stalk's lower end), scene frame
  std::unique_ptr<RayScene> alone;  // the bunch alone, unshifted: its amodal mask
};

// The case's bunches and the scene's bunch: one, or with `vine_row:` the row of them
// exactly as protocol classification builds it (bench/protocols/classification.cpp).
struct CaseScene {
  std::vector<CaseBunch> bunches;
  Bunch scene_bunch;
};
CaseScene case_scene(const Scene& scene, const BunchJob& job) {
  CaseScene c;
  std::vector<Bunch> originals;
  if (scene.vine_row) {
    for (std::size_t k = 0; k < vine_row_anchors(*scene.vine_row).size(); ++k)
      originals.push_back(generate_bunch(job.params, derive_seed(job.seed, 0x40000 + k)));
    c.scene_bunch = vine_row(originals, *scene.vine_row, derive_seed(job.seed, 0x4a1e));
  } else {
    originals.push_back(generate_bunch(job.params, job.seed));
    c.scene_bunch = originals.front();
  }
  const std::vector<Vec3> anchors = scene.vine_row ? vine_row_anchors(*scene.vine_row) : std::vector<Vec3>{};
  int berry0 = 0, stem0 = 0;
  for (std::size_t k = 0; k < originals.size(); ++k) {
    CaseBunch b;
    b.original = std::move(originals[k]);
    if (scene.vine_row) {  // as vine_row() hangs it: its peduncle's upper end on the anchor
      const Bunch& o = b.original;
      const Vec3 hang = o.peduncle >= 0 ? o.stems[static_cast<std::size_t>(o.peduncle)].end : o.top;
      b.shift = anchors[k] - hang;
    }
    b.berry0 = berry0, b.stem0 = stem0;
    berry0 += static_cast<int>(b.original.berries.size());
    stem0 += static_cast<int>(b.original.stems.size());
    const double z = first_branch_height(b.original);
    b.branch_z = std::isfinite(z) ? z + b.shift.z() : -std::numeric_limits<double>::infinity();
    b.alone = std::make_unique<RayScene>(b.original);
    c.bunches.push_back(std::move(b));
  }
  return c;
}

// The bunch a berry or stem of the scene's bunch belongs to.
int bunch_of(const std::vector<CaseBunch>& bunches, int index, bool stem) {
  for (std::size_t k = bunches.size(); k-- > 0;) {
    if (index >= (stem ? bunches[k].stem0 : bunches[k].berry0)) return static_cast<int>(k);
  }
  return 0;
}

// An instance is (category, index): the bunch's number in the case, the berry's or
// cane's index in the scene, the leaf's fan.
std::int64_t code(int category, std::int64_t index) { return (static_cast<std::int64_t>(category) << 40) | index; }
int code_category(std::int64_t c) { return static_cast<int>(c >> 40); }
std::int64_t code_index(std::int64_t c) { return c & ((std::int64_t{1} << 40) - 1); }

// What a pixel sees, with the instances it belongs to (fine: berry, stalk, leaf, cane,
// or the bunch for its other stems; coarse: its bunch or -1).
struct PixelLabel {
  std::int64_t fine = -1;
  int bunch = -1;
  float depth = 0;  // m along the optical axis, 0: nothing
  std::uint8_t semantic = 0;
};

// Per leaf triangle, its leaf: the leaves are fans about a centre vertex
// (synth/foliage.cpp), numbered in the order their centres first appear.
std::vector<int> leaf_of_triangle(const Foliage& f, std::vector<int>& centre) {
  std::vector<int> out(f.triangles.size());
  std::map<int, int> index;
  for (std::size_t t = 0; t < f.triangles.size(); ++t) {
    auto [it, added] = index.emplace(f.triangles[t][0], static_cast<int>(centre.size()));
    if (added) centre.push_back(f.triangles[t][0]);
    out[t] = it->second;
  }
  return out;
}

struct LabelScene {
  const RayScene* rays = nullptr;
  std::optional<RayRenderScene> render;  // the row copies the ray and Cycles images show
  std::vector<int> leaf_of_tri, leaf_centre;
  std::vector<std::vector<int>> leaf_triangles;  // per leaf
};

std::vector<PixelLabel> label_pixels(const LabelScene& ls, const CaseScene& cs, const Camera& cam) {
  const int W = cam.K.width, H = cam.K.height;
  std::vector<PixelLabel> px(static_cast<std::size_t>(W) * H);
  const RayScene& rays = *ls.rays;
  const int stems = static_cast<int>(cs.scene_bunch.stems.size());
  const Eigen::Isometry3d to_cam = cam.pose.inverse();
  for_rows(H, [&](int v0, int v1) {
    std::vector<double> uv(2 * static_cast<std::size_t>(W));
    std::vector<Hit> hits(static_cast<std::size_t>(W));
    const PixelRays at = cam.pixel_rays();
    for (int v = v0; v < v1; ++v) {
      for (int u = 0; u < W; ++u) uv[2 * u] = u + 0.5, uv[2 * u + 1] = v + 0.5;
      rays.intersect_image_points(at, uv.data(), static_cast<std::size_t>(W), hits.data(), true);
      for (int u = 0; u < W; ++u) {
        const Hit& h = hits[static_cast<std::size_t>(u)];
        PixelLabel& p = px[static_cast<std::size_t>(v) * W + u];
        if (!h.valid() || h.part == Part::None) continue;
        p.depth = static_cast<float>((to_cam * h.point).z());
        p.semantic = static_cast<std::uint8_t>(static_cast<int>(h.part) + 1);
        switch (h.part) {
          case Part::Berry:
            p.bunch = bunch_of(cs.bunches, h.primitive, false);
            p.fine = code(kBerry, h.primitive);
            break;
          case Part::Pedicel:
          case Part::Rachis:
          case Part::Peduncle: {
            p.bunch = bunch_of(cs.bunches, h.primitive, true);
            const bool stalk = h.part == Part::Peduncle ||
                               (h.part == Part::Rachis && h.point.z() > cs.bunches[static_cast<std::size_t>(p.bunch)].branch_z);
            p.fine = stalk ? code(kStalk, p.bunch) : code(kBunch, p.bunch);
            break;
          }
          case Part::Leaf:
            p.fine = code(kLeaf, ls.leaf_of_tri[static_cast<std::size_t>(h.primitive)]);
            break;
          case Part::Cane:
            p.fine = code(kCane, h.primitive - stems);
            break;
          default:  // trellis wires and posts, a backdrop: seen, not annotated
            break;
        }
      }
    }
  });
  return px;
}

struct Box {
  int u0 = 1 << 30, v0 = 1 << 30, u1 = -1, v1 = -1;  // inclusive
  void add(int u, int v) { u0 = std::min(u0, u), v0 = std::min(v0, v), u1 = std::max(u1, u), v1 = std::max(v1, v); }
  void add(const Box& b) {
    if (b.u1 >= 0) add(b.u0, b.v0), add(b.u1, b.v1);
  }
  bool empty() const { return u1 < 0; }
  int w() const { return u1 - u0 + 1; }
  int h() const { return v1 - v0 + 1; }
};

// The pixel rectangle [u0, u1) x [v0, v1) holding the image of the convex hull of
// `points` (world, m), clipped to the image; the whole image when one is behind the
// camera's plane.
Box hull_pixels(const Camera& cam, const std::vector<Vec3>& points) {
  Box box;
  const Eigen::Isometry3d to_cam = cam.pose.inverse();
  double u0 = 1e300, v0 = 1e300, u1 = -1e300, v1 = -1e300;
  for (const Vec3& w : points) {
    const Vec3 p = to_cam * w;
    if (p.z() <= 1e-6) {
      box.add(0, 0), box.add(cam.K.width - 1, cam.K.height - 1);
      return box;
    }
    const double u = cam.K.fx * p.x() / p.z() + cam.K.cx, v = cam.K.fy * p.y() / p.z() + cam.K.cy;
    u0 = std::min(u0, u), v0 = std::min(v0, v), u1 = std::max(u1, u), v1 = std::max(v1, v);
  }
  // Pixel (u, v) spans [u, u + 1) here (sensors/camera.h): its centre u + 0.5.
  const int a0 = std::max(0, static_cast<int>(std::floor(u0)) - 1), b0 = std::max(0, static_cast<int>(std::floor(v0)) - 1);
  const int a1 = std::min(cam.K.width - 1, static_cast<int>(std::ceil(u1)) + 1),
            b1 = std::min(cam.K.height - 1, static_cast<int>(std::ceil(v1)) + 1);
  if (a0 <= a1 && b0 <= b1) box.add(a0, b0), box.add(a1, b1);
  return box;
}
// The corners of the cube about a ball: its hull holds the ball.
void add_ball(std::vector<Vec3>& points, const Vec3& c, double r) {
  for (int k = 0; k < 8; ++k) points.emplace_back(c + r * Vec3(k & 1 ? 1 : -1, k & 2 ? 1 : -1, k & 4 ? 1 : -1));
}

// The pixels of `box` whose centre ray `hit(ray)` says meets the object: a box-local mask.
template <class HitTest>
void object_mask(const Camera& cam, const Box& box, HitTest hit, std::vector<std::uint8_t>& m) {
  m.assign(box.empty() ? 0 : static_cast<std::size_t>(box.w()) * box.h(), 0);
  if (box.empty()) return;
  const PixelRays at = cam.pixel_rays();
  for (int v = box.v0; v <= box.v1; ++v)
    for (int u = box.u0; u <= box.u1; ++u)
      if (hit(at(u + 0.5, v + 0.5))) m[static_cast<std::size_t>(v - box.v0) * box.w() + (u - box.u0)] = 1;
}

bool ray_sphere(const Ray& r, const Vec3& c, double radius) {
  const Vec3 oc = r.origin - c;
  const double b = oc.dot(r.direction), q = oc.squaredNorm() - radius * radius;
  const double disc = b * b - q;
  return disc >= 0 && -b + std::sqrt(disc) > 0;
}

// Moeller-Trumbore, two-sided.
bool ray_triangle(const Ray& r, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 e1 = b - a, e2 = c - a, p = r.direction.cross(e2);
  const double det = e1.dot(p);
  if (std::abs(det) < 1e-18) return false;
  const double inv = 1 / det;
  const Vec3 s = r.origin - a;
  const double u = s.dot(p) * inv;
  if (u < 0 || u > 1) return false;
  const Vec3 q = s.cross(e1);
  const double v = r.direction.dot(q) * inv;
  if (v < 0 || u + v > 1) return false;
  return e2.dot(q) * inv > 0;
}

Json rle_json(const Rle& r) { return Json{{"size", {r.height, r.width}}, {"counts", rle_string(r)}}; }
Json box_json(const std::array<double, 4>& b) { return Json::array({b[0], b[1], b[2], b[3]}); }
Json vec_json(const Vec3& v) { return Json::array({v.x(), v.y(), v.z()}); }

std::string png16(int w, int h, const std::vector<std::uint16_t>& px) {
  std::vector<unsigned char> buf;
  cv::imencode(".png", cv::Mat(h, w, CV_16UC1, const_cast<std::uint16_t*>(px.data())), buf);
  return {buf.begin(), buf.end()};
}
std::string png_rgb(int w, int h, const std::vector<std::uint8_t>& rgb) {  // W x H x 3
  cv::Mat bgr;
  cv::cvtColor(cv::Mat(h, w, CV_8UC3, const_cast<std::uint8_t*>(rgb.data())), bgr, cv::COLOR_RGB2BGR);
  std::vector<unsigned char> buf;
  cv::imencode(".png", bgr, buf);  // OpenCV's level 1: 3x faster than libpng's default, 10 % larger
  return {buf.begin(), buf.end()};
}
std::string png8(int w, int h, const std::vector<std::uint8_t>& px) {
  std::vector<unsigned char> buf;
  cv::imencode(".png", cv::Mat(h, w, CV_8UC1, const_cast<std::uint8_t*>(px.data())), buf);
  return {buf.begin(), buf.end()};
}
std::string tiff32(int w, int h, const std::vector<float>& px) {
  std::vector<unsigned char> buf;
  // Uncompressed: OpenCV 4.6 writes 32-bit float TIFF without compression (or lossy SGILOG).
  cv::imencode(".tiff", cv::Mat(h, w, CV_32FC1, const_cast<float*>(px.data())), buf);
  return {buf.begin(), buf.end()};
}

// The largest outer contour of a box-local mask, in image pixels (pixel corners are
// not traced: the polygon runs through the boundary pixels' centres, as OpenCV's).
std::vector<cv::Point> outline(const std::vector<std::uint8_t>& m, const Box& b) {
  cv::Mat mat(b.h() + 2, b.w() + 2, CV_8UC1, cv::Scalar(0));
  for (int v = 0; v < b.h(); ++v)
    for (int u = 0; u < b.w(); ++u) mat.at<std::uint8_t>(v + 1, u + 1) = m[static_cast<std::size_t>(v) * b.w() + u];
  std::vector<std::vector<cv::Point>> contours;
  cv::findContours(mat, contours, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_SIMPLE);
  std::size_t best = 0;
  double best_area = -1;
  for (std::size_t i = 0; i < contours.size(); ++i) {
    const double a = cv::contourArea(contours[i]) + static_cast<double>(contours[i].size());
    if (a > best_area) best = i, best_area = a;
  }
  std::vector<cv::Point> out;
  if (contours.empty()) return out;
  for (const cv::Point& p : contours[best]) out.emplace_back(p.x - 1 + b.u0, p.y - 1 + b.v0);
  return out;
}

std::string fixed(double x, int digits = 6) {
  char s[32];
  std::snprintf(s, sizeof s, "%.*f", digits, x);
  return s;
}

// The bunch instance's 3D truth: the original's, moved where the scene hangs it.
Json bunch_truth(const CaseBunch& b, const BunchJob& job, std::int64_t uid, int split) {
  const GroundTruth t = compute_ground_truth(b.original, job.params.density);
  Json j;
  j["bunch_uid"] = uid;
  j["split"] = kSplitNames[static_cast<std::size_t>(split)];
  j["preset"] = job.preset;
  j["bunch_seed"] = job.seed;
  j["volume"] = t.volume.solid;
  j["envelope_volume"] = t.envelope_volume;
  j["mass"] = t.mass;
  j["berry_count"] = t.berry_count;
  j["height"] = t.height;
  j["max_diameter"] = t.max_diameter;
  j["pca_extent"] = vec_json(t.pca_extent);
  j["cutting_point"] = vec_json(t.cutting_point + b.shift);
  Json berries = Json::array();
  for (const Berry& berry : b.original.berries)
    berries.push_back({{"centre", vec_json(berry.centre + b.shift)}, {"radius", berry.radius}});
  j["berries"] = std::move(berries);
  return j;
}

struct Writer {
  const SceneSet& set;
  std::filesystem::path out;
  std::int64_t case_index = 0;
  int condition = 0;
  std::size_t annotations = 0;
  int images = 0;
};

std::string image_stem(std::int64_t case_index, std::size_t view) {
  char s[40];
  std::snprintf(s, sizeof s, "%06lld_%03zu", static_cast<long long>(case_index), view);
  return s;
}

// One view: its images and its COCO image record with the annotations.
Json write_view(const Scene& scene, const LabelScene& ls, const CaseScene& cs, const ScanView& view, std::size_t k,
                std::int64_t case_index, int split, const std::vector<std::int64_t>& bunch_uid,
                const std::filesystem::path& out, DatasetTiming& timing) {
  const OrganisedCloud& cloud = view.cloud;
  if (cloud.left_image.empty())
    throw InputError(scene.path + ": sensor: a dataset needs colour images (type stereo_rgb), not " + scene.sensor->type());
  const Camera& cam = view.camera;
  const int W = cam.K.width, H = cam.K.height;
  if (W != cloud.width || H != cloud.height || W > 65535 || H > 65535)
    throw InputError(scene.path + ": sensor: image size " + std::to_string(W) + " x " + std::to_string(H) +
                     " does not fit a dataset");
  const auto t_labels = std::chrono::steady_clock::now();
  const std::vector<PixelLabel> px = label_pixels(ls, cs, cam);

  // Instances: every fine code seen, and each bunch with a pixel; sorted, numbered 1..n.
  std::map<std::int64_t, Box> seen;
  std::map<std::int64_t, std::int64_t> count;
  for (int v = 0; v < H; ++v)
    for (int u = 0; u < W; ++u) {
      const PixelLabel& p = px[static_cast<std::size_t>(v) * W + u];
      if (p.fine >= 0) seen[p.fine].add(u, v), ++count[p.fine];
      if (p.bunch >= 0 && p.fine != code(kBunch, p.bunch)) seen[code(kBunch, p.bunch)].add(u, v), ++count[code(kBunch, p.bunch)];
    }
  std::map<std::int64_t, int> id;
  for (const auto& [c, box] : seen) {
    (void)box;
    id.emplace(c, static_cast<int>(id.size()) + 1);
  }
  if (id.size() > 65535) throw std::runtime_error("more than 65535 instances in one image");

  const std::string split_name = kSplitNames[static_cast<std::size_t>(split)];
  const std::string stem = image_stem(case_index, k);
  std::vector<std::uint16_t> inst(px.size(), 0), depth_mm(px.size(), 0);
  std::vector<std::uint8_t> sem(px.size(), 0);
  std::vector<float> depth(px.size(), 0.0f);
  for (std::size_t i = 0; i < px.size(); ++i) {
    const PixelLabel& p = px[i];
    if (p.fine >= 0) inst[i] = static_cast<std::uint16_t>(id.at(p.fine));
    else if (p.bunch >= 0) inst[i] = static_cast<std::uint16_t>(id.at(code(kBunch, p.bunch)));
    sem[i] = p.semantic;
    depth[i] = p.depth;
    depth_mm[i] = static_cast<std::uint16_t>(std::clamp(std::lround(p.depth * 1000.0), 0L, 65535L));
  }
  timing.labels += seconds_since(t_labels);
  const auto t_images = std::chrono::steady_clock::now();
  auto file = [&](const char* folder, const std::string& ext) {
    return std::filesystem::path(folder) / split_name / (stem + ext);
  };
  write_file_atomic(out / file("images", ".png"), png_rgb(W, H, cloud.left_image));
  write_file_atomic(out / file("depth", ".png"), png16(W, H, depth_mm));
  if (scene.dataset.float_depth) write_file_atomic(out / file("depth", ".tiff"), tiff32(W, H, depth));
  write_file_atomic(out / file("instances", ".png"), png16(W, H, inst));
  write_file_atomic(out / file("semantic", ".png"), png8(W, H, sem));
  timing.write += seconds_since(t_images);
  const auto t_masks = std::chrono::steady_clock::now();

  const std::int64_t image_id = case_index * 1000 + static_cast<std::int64_t>(k) + 1;
  Json image;
  image["id"] = image_id;
  image["file_name"] = file("images", ".png").generic_string();
  image["width"] = W, image["height"] = H;
  image["depth_file"] = file("depth", ".png").generic_string();
  if (scene.dataset.float_depth) image["depth_float_file"] = file("depth", ".tiff").generic_string();
  image["instance_file"] = file("instances", ".png").generic_string();
  image["semantic_file"] = file("semantic", ".png").generic_string();
  image["intrinsics"] = {{"fx", cam.K.fx}, {"fy", cam.K.fy}, {"cx", cam.K.opencv_cx()}, {"cy", cam.K.opencv_cy()}};
  Json pose = Json::array();
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) pose.push_back(cam.pose.matrix()(r, c));
  image["pose"] = std::move(pose);  // camera to world, 4 x 4 row-major, m
  image["case"] = case_index;
  image["view"] = k;
  image["rig_view"] = view.rig.name;

  // Annotations: each instance's masks in parallel, gathered in order.
  struct Instance {
    std::int64_t code;
    Box vbox;
  };
  std::vector<Instance> todo;
  for (const auto& [c, vbox] : seen)
    if (count[c] >= scene.dataset.min_pixels) todo.push_back({c, vbox});
  struct Annotation {
    Json json;
    std::string yolo, yolo_seg;
  };
  std::vector<Annotation> done(todo.size());
  tbb::parallel_for(std::size_t{0}, todo.size(), [&](std::size_t n) {
    const std::int64_t c = todo[n].code;
    const Box& vbox = todo[n].vbox;
    std::vector<std::uint8_t> vis, amo;
    const int cat = code_category(c);
    const std::int64_t index = code_index(c);
    const int iid = id.at(c);
    // Visible mask in its box.
    vis.assign(static_cast<std::size_t>(vbox.w()) * vbox.h(), 0);
    for (int v = vbox.v0; v <= vbox.v1; ++v)
      for (int u = vbox.u0; u <= vbox.u1; ++u) {
        const PixelLabel& p = px[static_cast<std::size_t>(v) * W + u];
        const bool in = p.fine == c || (cat == kBunch && p.bunch == index);
        vis[static_cast<std::size_t>(v - vbox.v0) * vbox.w() + (u - vbox.u0)] = in ? 1 : 0;
      }
    // Amodal mask: the object alone, tested in the image box of its hull.
    Box abox;
    std::vector<Vec3> hull;
    if (cat == kBerry) {
      const Berry& b = cs.scene_bunch.berries[static_cast<std::size_t>(index)];
      add_ball(hull, b.centre, b.radius);
      abox = hull_pixels(cam, hull);
      object_mask(cam, abox, [&](const Ray& r) { return ray_sphere(r, b.centre, b.radius); }, amo);
    } else if (cat == kBunch) {
      const CaseBunch& b = cs.bunches[static_cast<std::size_t>(index)];
      const Vec3 lo = b.alone->bunch_min() + b.shift, hi = b.alone->bunch_max() + b.shift;
      for (int q = 0; q < 8; ++q) hull.emplace_back(q & 1 ? hi.x() : lo.x(), q & 2 ? hi.y() : lo.y(), q & 4 ? hi.z() : lo.z());
      abox = hull_pixels(cam, hull);
      object_mask(cam, abox, [&](const Ray& r) {
        return b.alone->intersect(Ray{r.origin - b.shift, r.direction}, true).valid();
      }, amo);
    } else if (cat == kStalk) {
      const CaseBunch& b = cs.bunches[static_cast<std::size_t>(index)];
      std::vector<const Stem*> pieces;
      for (std::size_t s = 0; s < b.original.stems.size(); ++s) {
        const Stem& st = cs.scene_bunch.stems[static_cast<std::size_t>(b.stem0) + s];
        const bool take = st.part == Part::Peduncle ||
                          (st.part == Part::Rachis && std::max(st.start.z(), st.end.z()) > b.branch_z);
        if (!take) continue;
        pieces.push_back(&st);
        add_ball(hull, st.start, st.radius), add_ball(hull, st.end, st.radius);
      }
      abox = hull_pixels(cam, hull);
      object_mask(cam, abox, [&](const Ray& r) {
        for (const Stem* st : pieces) {
          double t;
          Vec3 normal;
          if (!ray_cylinder(*st, r.origin, r.direction, 0.0, t, normal)) continue;
          if (st->part == Part::Peduncle || (r.origin + t * r.direction).z() > b.branch_z) return true;
        }
        return false;
      }, amo);
    } else if (cat == kLeaf) {
      const Foliage& f = ls.rays->foliage();
      const auto& tris = ls.leaf_triangles[static_cast<std::size_t>(index)];
      for (int t : tris)
        for (int q : f.triangles[static_cast<std::size_t>(t)]) hull.push_back(f.vertices[static_cast<std::size_t>(q)]);
      abox = hull_pixels(cam, hull);
      object_mask(cam, abox, [&](const Ray& r) {
        for (int t : tris) {
          const auto& tri = f.triangles[static_cast<std::size_t>(t)];
          if (ray_triangle(r, f.vertices[static_cast<std::size_t>(tri[0])], f.vertices[static_cast<std::size_t>(tri[1])],
                           f.vertices[static_cast<std::size_t>(tri[2])]))
            return true;
        }
        return false;
      }, amo);
    } else {  // cane
      const Stem& st = ls.rays->foliage().canes[static_cast<std::size_t>(index)];
      add_ball(hull, st.start, st.radius), add_ball(hull, st.end, st.radius);
      abox = hull_pixels(cam, hull);
      object_mask(cam, abox, [&](const Ray& r) {
        double t;
        Vec3 normal;
        return ray_cylinder(st, r.origin, r.direction, 0.0, t, normal);
      }, amo);
    }
    // Visible within amodal, always (the two tests agree to rounding at the rim).
    Box ubox = abox;
    ubox.add(vbox);
    std::vector<std::uint8_t> merged(static_cast<std::size_t>(ubox.w()) * ubox.h(), 0);
    for (int v = abox.v0; !abox.empty() && v <= abox.v1; ++v)
      for (int u = abox.u0; u <= abox.u1; ++u)
        merged[static_cast<std::size_t>(v - ubox.v0) * ubox.w() + (u - ubox.u0)] = amo[static_cast<std::size_t>(v - abox.v0) * abox.w() + (u - abox.u0)];
    for (int v = vbox.v0; v <= vbox.v1; ++v)
      for (int u = vbox.u0; u <= vbox.u1; ++u)
        merged[static_cast<std::size_t>(v - ubox.v0) * ubox.w() + (u - ubox.u0)] |= vis[static_cast<std::size_t>(v - vbox.v0) * vbox.w() + (u - vbox.u0)];
    const Rle vr = rle_encode(vis.data(), vbox.u0, vbox.v0, vbox.w(), vbox.h(), W, H);
    const Rle ar = rle_encode(merged.data(), ubox.u0, ubox.v0, ubox.w(), ubox.h(), W, H);
    const std::uint64_t area = rle_area(vr), amodal_area = rle_area(ar);
    const auto bbox = rle_box(vr);
    Json a;
    a["id"] = image_id * 65536 + iid;
    a["image_id"] = image_id;
    a["category_id"] = cat;
    a["instance_id"] = iid;
    a["segmentation"] = rle_json(vr);
    a["area"] = area;
    a["bbox"] = box_json(bbox);
    a["iscrowd"] = 0;
    a["amodal_segmentation"] = rle_json(ar);
    a["amodal_area"] = amodal_area;
    a["amodal_bbox"] = box_json(rle_box(ar));
    a["visible_fraction"] = static_cast<double>(area) / static_cast<double>(std::max<std::uint64_t>(amodal_area, 1));
    if (cat == kBunch || cat == kStalk) a["bunch_uid"] = bunch_uid[static_cast<std::size_t>(index)];
    if (cat == kBerry) {
      const int kb = bunch_of(cs.bunches, static_cast<int>(index), false);
      a["bunch_uid"] = bunch_uid[static_cast<std::size_t>(kb)];
      a["berry"] = index - cs.bunches[static_cast<std::size_t>(kb)].berry0;  // in its bunch's truth list
    }
    if (cat == kLeaf) a["leaf"] = index;
    if (cat == kCane) a["cane"] = index;
    done[n].json = std::move(a);
    // YOLO: class, box centre and size over the image's size; the outline likewise.
    const int cls = cat - 1;
    done[n].yolo = std::to_string(cls) + " " + fixed((bbox[0] + 0.5 * bbox[2]) / W) + " " + fixed((bbox[1] + 0.5 * bbox[3]) / H) +
            " " + fixed(bbox[2] / W) + " " + fixed(bbox[3] / H) + "\n";
    const std::vector<cv::Point> poly = outline(vis, vbox);
    if (poly.size() >= 3) {
      std::string& yolo_seg = done[n].yolo_seg;
      yolo_seg = std::to_string(cls);
      for (const cv::Point& p : poly) yolo_seg += " " + fixed((p.x + 0.5) / W) + " " + fixed((p.y + 0.5) / H);
      yolo_seg += "\n";
    }
  });
  Json anns = Json::array();
  std::string yolo, yolo_seg;
  for (Annotation& d : done) {
    anns.push_back(std::move(d.json));
    yolo += d.yolo;
    yolo_seg += d.yolo_seg;
  }
  timing.masks += seconds_since(t_masks);
  const auto t_write = std::chrono::steady_clock::now();
  write_file_atomic(out / file("labels", ".txt"), yolo);
  write_file_atomic(out / file("labels_seg", ".txt"), yolo_seg);
  timing.write += seconds_since(t_write);
  image["annotations"] = std::move(anns);
  return image;
}

double peak_rss_mb() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_maxrss) / 1024.0;  // Linux: KiB
}

// The record that ties a folder to its scene: a resumed dataset must match it.
Json dataset_key(const SceneSet& set) {
  Json j;
  j["format"] = "grapebench-dataset-1";
  Json conds = Json::array();
  for (const auto& c : set.conditions) conds.push_back({{"condition", c.label}, {"scene", scene_json(c.scene)}});
  j["conditions"] = std::move(conds);
  return j;
}

Json categories_json() {
  Json cats = Json::array();
  for (const auto& c : kDatasetCategories)
    cats.push_back({{"id", c.id}, {"name", c.name}, {"supercategory", "grapevine"}, {"description", c.doc}});
  return cats;
}

}  // namespace

DatasetSummary write_dataset(const SceneSet& set, const DatasetRunOptions& o) {
  const auto t0 = std::chrono::steady_clock::now();
  const Scene& base = set.base;
  if (!base.sensor || !base.rig) throw InputError(base.path + ": a dataset needs `sensor:` and `rig:` sections");
  for (const auto& c : set.conditions) {
    if (c.scene.sensor->type() != "stereo_rgb")
      throw InputError(base.path + ": sensor: a dataset needs a colour camera (type stereo_rgb), not " +
                       c.scene.sensor->type());
  }
  const std::filesystem::path key_file = o.out / "dataset_scene.json";
  const Json key = dataset_key(set);
  std::error_code ec;
  const bool exists = std::filesystem::exists(o.out, ec);
  if (exists && !std::filesystem::is_directory(o.out, ec))
    throw InputError(o.out.string() + ": exists and is not a folder");
  const bool holds_files = exists && std::filesystem::directory_iterator(o.out, ec) != std::filesystem::directory_iterator();
  if (holds_files) {
    if (!o.resume)
      throw InputError(o.out.string() + ": the folder holds files; give an empty or new folder, or --resume to "
                       "continue a dataset of this scene");
    Json old;
    try {
      std::ifstream in(key_file);
      old = Json::parse(in);
    } catch (const std::exception&) {
      throw InputError(key_file.string() + ": missing or unreadable: the folder holds no dataset to resume");
    }
    if (old != key)
      throw InputError(key_file.string() + ": the dataset in this folder was written from another scene (or "
                       "another version); never mixed: give a new folder");
  }
  std::filesystem::create_directories(o.out / "parts");
  for (const char* folder : {"images", "depth", "instances", "semantic", "labels", "labels_seg"})
    for (const char* split : kSplitNames) std::filesystem::create_directories(o.out / folder / split);
  if (!holds_files) write_file_atomic(key_file, key.dump(1) + "\n");

  const int threads = o.threads > 0 ? o.threads : static_cast<int>(tbb::info::default_concurrency());
  tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(threads));

  struct CaseRef {
    int condition;
    BunchJob job;
  };
  std::vector<CaseRef> cases;
  for (std::size_t c = 0; c < set.conditions.size(); ++c)
    for (const BunchJob& job : bunch_jobs(set.conditions[c].scene)) cases.push_back({static_cast<int>(c), job});
  const std::size_t bunches_per_case = base.vine_row ? vine_row_anchors(*base.vine_row).size() : 1;

  DatasetSummary summary;
  Progress progress("case", static_cast<int>(cases.size()), o.verbosity);
  auto part_path = [&](std::size_t i) {
    char s[32];
    std::snprintf(s, sizeof s, "case_%06zu.json", i);
    return o.out / "parts" / s;
  };
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const Condition& cond = set.conditions[static_cast<std::size_t>(cases[i].condition)];
    const Scene& scene = cond.scene;
    const BunchJob& job = cases[i].job;
    if (std::filesystem::exists(part_path(i))) {
      ++summary.cases_resumed;
      progress.done("case " + std::to_string(i) + " (already written)");
      continue;
    }
    const int split = dataset_split(job.seed, scene.dataset);
    CaseScene cs = case_scene(scene, job);
    const RayScene rays = scene_rays(scene, cs.scene_bunch, job.seed);
    LabelScene ls;
    ls.rays = &rays;
    const auto& params = static_cast<const StereoRgb&>(*scene.sensor).params();
    if (params.renderer != StereoRgbParams::Renderer::OpenGl) {
      ls.render.emplace(ray_render_scene(rays, params.appearance));
      ls.rays = &ls.render->rays();
    }
    ls.leaf_of_tri = leaf_of_triangle(ls.rays->foliage(), ls.leaf_centre);
    ls.leaf_triangles.assign(ls.leaf_centre.size(), {});
    for (std::size_t t = 0; t < ls.leaf_of_tri.size(); ++t)
      ls.leaf_triangles[static_cast<std::size_t>(ls.leaf_of_tri[t])].push_back(static_cast<int>(t));
    std::vector<std::int64_t> uid;
    Json part;
    part["case"] = i;
    part["condition"] = cond.label;
    part["bunch_seed"] = job.seed;
    part["split"] = kSplitNames[static_cast<std::size_t>(split)];
    Json truths = Json::array();
    for (std::size_t k = 0; k < cs.bunches.size(); ++k) {
      uid.push_back(static_cast<std::int64_t>(i * bunches_per_case + k));
      truths.push_back(bunch_truth(cs.bunches[k], job, uid.back(), split));
    }
    Json images = Json::array();
    const std::uint64_t scan_seed = derive_seed(job.seed, 0x5ca9);  // the stream of `grapebench scan` and `run`
    scan_views(rays, *scene.sensor, *scene.rig, scene.background, scan_seed, [&](ScanView&& view, std::size_t k) {
      if (k >= 1000) throw InputError(scene.path + ": rig: a dataset takes at most 1000 views per bunch");
      summary.timing.capture += view.seconds;
      images.push_back(write_view(scene, ls, cs, view, k, static_cast<std::int64_t>(i), split, uid, o.out, summary.timing));
      ++summary.images;
    });
    part["images"] = std::move(images);
    part["bunches"] = std::move(truths);
    write_file_atomic(part_path(i), part.dump() + "\n");
    ++summary.cases;
    progress.done("case " + std::to_string(i) + ", " + kSplitNames[static_cast<std::size_t>(split)]);
  }

  // The dataset's files, streamed from the parts: one part in memory at a time.
  auto read_part = [&](std::size_t i) {
    std::ifstream in(part_path(i));
    return Json::parse(in);
  };
  const Json cats = categories_json();
  for (int s = 0; s < 3; ++s) {
    const std::string name = kSplitNames[static_cast<std::size_t>(s)];
    const std::filesystem::path tmp = o.out / ("annotations_" + name + ".json.part");
    {
      std::ofstream f(tmp, std::ios::binary);
      f << "{\"info\":" << Json{{"description", "grapebench dataset of " + base.name}, {"version", build_info_json()["version"]}, {"split", name}}.dump()
        << ",\n\"categories\":" << cats.dump() << ",\n\"images\":[";
      bool first = true;
      for (std::size_t i = 0; i < cases.size(); ++i) {
        Json part = read_part(i);
        if (part["split"] != name) continue;
        for (Json& im : part["images"]) {
          im.erase("annotations");
          f << (first ? "\n" : ",\n") << im.dump();
          first = false;
          ++summary.split_images[static_cast<std::size_t>(s)];
        }
      }
      f << "],\n\"annotations\":[";
      first = true;
      for (std::size_t i = 0; i < cases.size(); ++i) {
        Json part = read_part(i);
        if (part["split"] != name) continue;
        for (const Json& im : part["images"])
          for (const Json& a : im["annotations"]) {
            f << (first ? "\n" : ",\n") << a.dump();
            first = false;
            ++summary.annotations;
          }
      }
      f << "]}\n";
      if (!f) throw std::runtime_error(tmp.string() + ": write failed");
    }
    std::filesystem::create_directories(o.out / "annotations");
    std::filesystem::rename(tmp, o.out / "annotations" / (name + ".json"));
  }
  {
    const std::filesystem::path tmp = o.out / "truth.json.part";
    std::ofstream f(tmp, std::ios::binary);
    f << "{\"bunches\":[";
    bool first = true;
    for (std::size_t i = 0; i < cases.size(); ++i) {
      const Json part = read_part(i);
      for (const Json& b : part["bunches"]) {
        f << (first ? "\n" : ",\n") << b.dump();
        first = false;
      }
    }
    f << "]}\n";
    f.close();
    if (!f) throw std::runtime_error(tmp.string() + ": write failed");
    std::filesystem::rename(tmp, o.out / "truth.json");
  }
  std::string yaml = "# YOLO data file (Ultralytics): boxes in labels/, polygons in labels_seg/\npath: .\n"
                     "train: images/train\nval: images/val\ntest: images/test\nnames:\n";
  for (const auto& c : kDatasetCategories) yaml += "  " + std::to_string(c.id - 1) + ": " + c.name + "\n";
  write_file_atomic(o.out / "dataset.yaml", yaml);
  summary.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  summary.peak_rss_mb = peak_rss_mb();
  Json manifest = manifest_json(set, {}, threads);
  manifest["dataset"] = {{"categories", cats},
                         {"images", {{"train", summary.split_images[0]}, {"val", summary.split_images[1]}, {"test", summary.split_images[2]}}},
                         {"annotations", summary.annotations},
                         {"cases", cases.size()}};
  write_file_atomic(o.out / "manifest.json", manifest.dump(1) + "\n");
  return summary;
}

}  // namespace grapebench
