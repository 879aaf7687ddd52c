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
#include "bench/image_truth.h"
#include "bench/protocols/capture.h"
#include "bench/protocols/stereo_pair.h"
#include "sensors/render/cycles_render.h"
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
std::vector<cv::Point> outline(const std::vector<std::uint8_t>& m, const PixelBox& b) {
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
  const ImageTruth truth = image_truth(ls, cs, cam, scene.dataset.min_pixels, true);
  timing.labels += truth.label_seconds;
  timing.masks += truth.mask_seconds;
  const std::string split_name = kSplitNames[static_cast<std::size_t>(split)];
  const std::string stem = image_stem(case_index, k);
  std::vector<std::uint16_t> depth_mm(truth.depth.size(), 0);
  for (std::size_t i = 0; i < truth.depth.size(); ++i)
    depth_mm[i] = static_cast<std::uint16_t>(std::clamp(std::lround(truth.depth[i] * 1000.0), 0L, 65535L));
  const auto t_images = std::chrono::steady_clock::now();
  auto file = [&](const char* folder, const std::string& ext) {
    return std::filesystem::path(folder) / split_name / (stem + ext);
  };
  // The camera's own JPEG file when its model compresses (camera.jpeg_quality), else PNG.
  const std::string colour_ext = cloud.left_jpeg.empty() ? ".png" : ".jpg";
  if (cloud.left_jpeg.empty()) {
    write_file_atomic(out / file("images", ".png"), png_rgb(W, H, cloud.left_image));
  } else {
    write_file_atomic(out / file("images", ".jpg"), std::string(cloud.left_jpeg.begin(), cloud.left_jpeg.end()));
  }
  write_file_atomic(out / file("depth", ".png"), png16(W, H, depth_mm));
  if (scene.dataset.float_depth) write_file_atomic(out / file("depth", ".tiff"), tiff32(W, H, truth.depth));
  write_file_atomic(out / file("instances", ".png"), png16(W, H, truth.instance_image));
  write_file_atomic(out / file("semantic", ".png"), png8(W, H, truth.semantic));
  timing.write += seconds_since(t_images);

  const std::int64_t image_id = case_index * 1000 + static_cast<std::int64_t>(k) + 1;
  Json image;
  image["id"] = image_id;
  image["file_name"] = file("images", colour_ext).generic_string();
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

  // Annotations: from each instance's masks, in parallel, gathered in order.
  const auto t_masks = std::chrono::steady_clock::now();
  struct Annotation {
    Json json;
    std::string yolo, yolo_seg;
  };
  std::vector<Annotation> done(truth.instances.size());
  tbb::parallel_for(std::size_t{0}, done.size(), [&](std::size_t n) {
    const ImageInstance& in = truth.instances[n];
    const int cat = in.category;
    const std::int64_t index = in.index;
    const int iid = in.id;
    const Rle& vr = in.visible;
    const Rle& ar = *in.amodal;
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
      a["bunch_uid"] = bunch_uid[static_cast<std::size_t>(in.bunch)];
      a["berry"] = in.berry;  // in its bunch's truth list
    }
    if (cat == kLeaf) a["leaf"] = index;
    if (cat == kCane) a["cane"] = index;
    done[n].json = std::move(a);
    // YOLO: class, box centre and size over the image's size; the outline likewise.
    const int cls = cat - 1;
    done[n].yolo = std::to_string(cls) + " " + fixed((bbox[0] + 0.5 * bbox[2]) / W) + " " + fixed((bbox[1] + 0.5 * bbox[3]) / H) +
            " " + fixed(bbox[2] / W) + " " + fixed(bbox[3] / H) + "\n";
    const std::vector<cv::Point> poly = outline(in.mask, in.box);
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
  const CyclesCacheScope cache(o.cycles_cache);
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
    const LabelScene ls = label_scene(scene, rays);
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
    // The stream of `grapebench scan` and `run`.
    scan_views(rays, *scene.sensor, *scene.rig, scene.background, scan_seed(job), [&](ScanView&& view, std::size_t k) {
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
