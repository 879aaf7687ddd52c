// The extension behind `import grapebench` (python/grapebench/__init__.py wraps it):
// scenes read with the harness's own strict readers, bunches with their exact truth as
// numpy arrays, the registered estimators on numpy clouds, and `run`. Documents cross
// as JSON text (the harness's own writers), turned into dicts on the Python side.
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <functional>
#include <optional>

#include "algorithms/registry.h"
#include "bench/protocols/capture.h"
#include "bench/protocols/registration_methods.h"
#include "bench/protocols/registry.h"
#include "bench/runner.h"
#include "bench/scoring/classes.h"
#include "bench/scoring/coco_eval.h"
#include "bench/scoring/detections.h"
#include "bench/scoring/images.h"
#include "bench/scoring/points.h"
#include "bench/scoring/scalars.h"
#include "bench/scoring/statistics.h"
#include "bench/scene.h"
#include "bench/scene_file.h"
#include "synth/config.h"
#include "synth/generate.h"
#include "synth/ground_truth.h"
#include "synth/io.h"
#include "synth/mesh.h"
#include "synth/union_mesh.h"
#include "sensors/rig.h"
#include "sensors/sensor_registry.h"

namespace py = pybind11;
using namespace grapebench;

namespace {

// A numpy array that owns a copy of `rows` x `cols` doubles (row-major).
py::array_t<double> matrix(std::size_t rows, std::size_t cols, const std::function<double(std::size_t, std::size_t)>& at) {
  py::array_t<double> a(std::vector<py::ssize_t>{static_cast<py::ssize_t>(rows), static_cast<py::ssize_t>(cols)});
  auto m = a.mutable_unchecked<2>();
  for (std::size_t i = 0; i < rows; ++i)
    for (std::size_t j = 0; j < cols; ++j) m(static_cast<py::ssize_t>(i), static_cast<py::ssize_t>(j)) = at(i, j);
  return a;
}

py::array_t<double> vector_of(std::size_t n, const std::function<double(std::size_t)>& at) {
  py::array_t<double> a(static_cast<py::ssize_t>(n));
  auto m = a.mutable_unchecked<1>();
  for (std::size_t i = 0; i < n; ++i) m(static_cast<py::ssize_t>(i)) = at(i);
  return a;
}

const BunchJob& job_of(const SceneSet& set, const std::vector<BunchJob>& jobs, int index) {
  if (index < 0 || static_cast<std::size_t>(index) >= jobs.size())
    throw InputError(set.base.path + ": bunch index " + std::to_string(index) + " out of range [0, " +
                     std::to_string(static_cast<long long>(jobs.size()) - 1) + "]");
  return jobs[static_cast<std::size_t>(index)];
}

// One bunch of the scene: its geometry as arrays and its ground-truth document (the
// one `grapebench synth` writes) as JSON text.
// With `mesh`, also its surface as `grapebench synth` writes it (the union of berries
// and stems, synth/union_mesh.h): vertices (V x 3, m), faces (F x 3), per face its part
// name index into mesh_parts and its berry (-1 for stems).
py::dict synth_bunch(const SceneSet& set, int index, bool mesh) {
  const std::vector<BunchJob> jobs = bunch_jobs(set.base);
  const BunchJob& job = job_of(set, jobs, index);
  GenerationReport report;
  Bunch b;
  GroundTruth truth;
  TriMesh surface;
  {
    py::gil_scoped_release free;  // other Python threads run while the bunch is made
    b = generate_bunch(job.params, job.seed, &report);
    truth = compute_ground_truth(b, job.params.density);
    if (mesh) surface = bunch_surface(b);
  }
  const BunchRecord record{job.preset, job.seed, job.index, job.params, report};
  py::dict d;
  d["preset"] = job.preset;
  d["index"] = job.index;
  d["seed"] = job.seed;
  d["berry_centres"] = matrix(b.berries.size(), 3, [&](std::size_t i, std::size_t j) { return b.berries[i].centre[static_cast<int>(j)]; });
  d["berry_radii"] = vector_of(b.berries.size(), [&](std::size_t i) { return b.berries[i].radius; });
  d["stem_starts"] = matrix(b.stems.size(), 3, [&](std::size_t i, std::size_t j) { return b.stems[i].start[static_cast<int>(j)]; });
  d["stem_ends"] = matrix(b.stems.size(), 3, [&](std::size_t i, std::size_t j) { return b.stems[i].end[static_cast<int>(j)]; });
  d["stem_radii"] = vector_of(b.stems.size(), [&](std::size_t i) { return b.stems[i].radius; });
  py::list parts;
  for (const Stem& s : b.stems) parts.append(std::string(part_name(s.part)));
  d["stem_parts"] = parts;
  d["cutting_point"] = vector_of(3, [&](std::size_t j) { return b.cutting_point[static_cast<int>(j)]; });
  d["truth_json"] = ground_truth_json(b, truth, record).dump();
  if (mesh) {
    // The faces and vertices the PLY file has (synth/mesh.h).
    const TriMesh& m = surface;
    const Exported e = exported(m);
    const std::size_t nf = e.faces.size();
    py::dict md;
    md["vertices"] = matrix(e.vertices.size(), 3, [&](std::size_t i, std::size_t j) {
      return m.vertices[static_cast<std::size_t>(e.vertices[i])][static_cast<int>(j)];
    });
    py::array_t<std::int32_t> faces(std::vector<py::ssize_t>{static_cast<py::ssize_t>(nf), 3});
    py::array_t<std::int32_t> berry(static_cast<py::ssize_t>(nf));
    py::list face_parts;
    for (std::size_t i = 0; i < nf; ++i) {
      const auto f = static_cast<std::size_t>(e.faces[i]);
      for (int k = 0; k < 3; ++k)
        faces.mutable_at(static_cast<py::ssize_t>(i), k) =
            e.vertex_map[static_cast<std::size_t>(m.faces[f][static_cast<std::size_t>(k)])];
      berry.mutable_at(static_cast<py::ssize_t>(i)) = m.face_berry[f];
      face_parts.append(part_name(m.face_part[f]));
    }
    md["faces"] = faces;
    md["face_berry"] = berry;
    md["face_part"] = face_parts;
    d["mesh"] = md;
  }
  return d;
}

// A numpy view of `data` (shape, strides in bytes) kept alive by `owner`: no copy.
template <class T>
py::array_t<T> view_of(const T* data, std::vector<py::ssize_t> shape, std::vector<py::ssize_t> strides,
                       const py::capsule& owner) {
  return py::array_t<T>(std::move(shape), std::move(strides), data, owner);
}

// One bunch's scan as `grapebench scan` captures it (the case's scan of `grapebench
// run`): per view the organised arrays (H x W), handed out without copies: each view
// is moved into an object its arrays' base owns. Where a pixel has no return, xyz and
// normal are NaN and rgb 0; where it sees nothing, berry is -1 and true_depth 0 (the
// sensor leaves those pixels unset). valid and label are copies (the sensor's pooled
// maps go back to their pool).
py::list scan_of(const SceneSet& set, int index) {
  static_assert(sizeof(Eigen::Vector3f) == 12 && sizeof(std::array<std::uint8_t, 3>) == 3, "packed pixels");
  const std::vector<BunchJob> jobs = bunch_jobs(set.base);
  const BunchJob& job = job_of(set, jobs, index);
  std::optional<CaseCapture> c;
  {
    py::gil_scoped_release free;
    c.emplace(capture_case(set.base, job));
  }
  py::list out;
  for (ScanView& v : c->scan.views) {
    auto* owned = new ScanView(std::move(v));
    const py::capsule base(owned, [](void* p) { delete static_cast<ScanView*>(p); });
    OrganisedCloud& oc = owned->cloud;
    const float nan = std::numeric_limits<float>::quiet_NaN();
    for (std::size_t i = 0; i < oc.size(); ++i) {
      if (!oc.valid[i]) oc.xyz[i].setConstant(nan), oc.normal[i].setConstant(nan), oc.rgb[i] = {0, 0, 0};
      if (oc.label[i] == static_cast<std::uint8_t>(Part::None)) oc.berry[i] = -1, oc.true_depth[i] = 0;
    }
    const py::ssize_t h = oc.height, w = oc.width;
    const auto bytes = [&](const ByteMap& m) {
      py::array_t<std::uint8_t> a(std::vector<py::ssize_t>{h, w});
      std::copy(m.begin(), m.end(), a.mutable_data());
      return a;
    };
    py::dict d;
    d["name"] = owned->rig.name;
    d["pose"] = matrix(4, 4, [&](std::size_t r, std::size_t k) {
      return owned->camera.pose.matrix()(static_cast<int>(r), static_cast<int>(k));
    });
    const Intrinsics& K = owned->camera.K;
    d["intrinsics"] = py::dict(py::arg("width") = K.width, py::arg("height") = K.height, py::arg("fx") = K.fx,
                               py::arg("fy") = K.fy, py::arg("cx") = K.opencv_cx(), py::arg("cy") = K.opencv_cy());
    d["valid"] = bytes(oc.valid);
    d["label"] = bytes(oc.label);
    d["berry"] = view_of(oc.berry.data(), {h, w}, {w * 4, 4}, base);
    d["xyz"] = view_of(oc.xyz.data()->data(), {h, w, 3}, {w * 12, 12, 4}, base);
    d["normal"] = view_of(oc.normal.data()->data(), {h, w, 3}, {w * 12, 12, 4}, base);
    d["rgb"] = view_of(oc.rgb.data()->data(), {h, w, 3}, {w * 3, 3, 1}, base);
    d["true_depth"] = view_of(oc.true_depth.data(), {h, w}, {w * 4, 4}, base);
    for (const auto& [key, image] : {std::pair{"left_image", &oc.left_image}, std::pair{"right_image", &oc.right_image}})
      d[key] = image->empty() ? py::object(py::none())
                              : py::object(view_of(image->data(), {h, w, 3}, {w * 3, 3, 1}, base));
    d["baseline"] = oc.baseline;
    out.append(d);
  }
  return out;
}

using Cloud = Eigen::Matrix<double, Eigen::Dynamic, 3>;
using Image = py::array_t<std::uint8_t, py::array::c_style | py::array::forcecast>;

// `key`: N x 3 finite rows (metres or unit vectors).
PointCloud finite_rows(const py::handle& a, const std::string& key) {
  const Cloud c = a.cast<Cloud>();
  for (Eigen::Index i = 0; i < c.rows(); ++i)
    if (!c.row(i).allFinite()) throw InputError(key + ": row " + std::to_string(i) + " is not finite (N x 3)");
  return c;
}

RgbImage rgb_image(const py::handle& h, const std::string& key) {
  const Image a = Image::ensure(h);
  if (!a || a.ndim() != 3 || a.shape(2) != 3 || a.shape(0) < 1 || a.shape(1) < 1)
    throw InputError(key + ": an H x W x 3 uint8 image (RGB, top row first)");
  RgbImage im;
  im.height = static_cast<int>(a.shape(0));
  im.width = static_cast<int>(a.shape(1));
  im.data.assign(a.data(), a.data() + a.size());
  return im;
}

double camera_value(const py::dict& camera, const char* key, double lo, double hi) {
  if (!camera.contains(key)) throw InputError(std::string("camera: needs '") + key + "'");
  const double v = camera[key].cast<double>();
  check_range(v, lo, hi, "camera", key);
  return v;
}

// What the estimator gets, from the keyword arrays: points (N x 3, m), normals,
// viewpoints (N x 3), colours (N x 3 uint8), classes (K names) and train_labels (N:
// a class index, or -1 where to score), left / right (H x W x 3 uint8) with camera
// {fx, fy, cx, cy (OpenCV's pixel centres), baseline (m, stereo pairs)}.
EstimatorInput input_of(const std::string& kind, const py::dict& a) {
  EstimatorInput in;
  const auto has = [&](const char* k) { return a.contains(k) && !a[k].is_none(); };
  if (has("points")) in.points = finite_rows(a["points"], "points");
  const auto per_point = [&](const char* k, PointCloud& out) {
    if (!has(k)) return;
    out = finite_rows(a[k], k);
    if (out.rows() != in.points.rows())
      throw InputError(std::string(k) + ": one row per point (" + std::to_string(in.points.rows()) + ")");
  };
  per_point("normals", in.normals);
  per_point("viewpoints", in.viewpoints);
  if (has("colours")) {
    const Image c = Image::ensure(a["colours"]);
    if (!c || c.ndim() != 2 || c.shape(1) != 3 || c.shape(0) != in.points.rows())
      throw InputError("colours: N x 3 uint8, one row per point (" + std::to_string(in.points.rows()) + ")");
    for (py::ssize_t i = 0; i < c.shape(0); ++i) in.colours.push_back({c.at(i, 0), c.at(i, 1), c.at(i, 2)});
  }
  if (kind == "labelled_cloud") {
    if (!has("classes") || !has("train_labels") || in.colours.empty())
      throw InputError("a labelled_cloud estimator needs points, colours, classes and train_labels");
    in.classes = a["classes"].cast<std::vector<std::string>>();
    in.train_labels = a["train_labels"].cast<std::vector<int>>();
    if (static_cast<Eigen::Index>(in.train_labels.size()) != in.points.rows())
      throw InputError("train_labels: one per point (" + std::to_string(in.points.rows()) + ")");
    for (std::size_t i = 0; i < in.train_labels.size(); ++i)
      if (in.train_labels[i] < -1 || in.train_labels[i] >= static_cast<int>(in.classes.size()))
        throw InputError("train_labels[" + std::to_string(i) + "]: a class index in [0, " +
                         std::to_string(in.classes.size() - 1) + "], or -1 where to score");
  }
  if (kind == "stereo_pair" || kind == "image") {
    if (!has("left") || !has("camera")) throw InputError("an " + kind + " estimator needs left and camera");
    auto pair = std::make_shared<StereoPair>();
    pair->left = rgb_image(a["left"], "left");
    if (has("right")) {
      pair->right = rgb_image(a["right"], "right");
      if (pair->right.width != pair->left.width || pair->right.height != pair->left.height)
        throw InputError("right: the left image's size");
    } else if (kind == "stereo_pair") {
      throw InputError("a stereo_pair estimator needs right too");
    }
    const py::dict camera = a["camera"].cast<py::dict>();
    const double w = pair->left.width, h = pair->left.height;
    pair->fx = camera_value(camera, "fx", 1, 1e6);
    pair->fy = camera_value(camera, "fy", 1, 1e6);
    pair->cx = camera_value(camera, "cx", -w, 2 * w);
    pair->cy = camera_value(camera, "cy", -h, 2 * h);
    pair->baseline = kind == "stereo_pair" ? camera_value(camera, "baseline", 1e-4, 10) : 0;
    in.frame = InputFrame{-1, "", -1, pair->left.width, pair->left.height, pair->fx, pair->fy, pair->cx, pair->cy};
    in.stereo = std::move(pair);
  } else if (in.points.rows() == 0) {
    throw InputError("points: an N x 3 array (metres)");
  }
  return in;
}

// A registered estimator on numpy input: `spec` is its scene entry as YAML (type and
// keys); `inputs` as input_of reads them, for the estimator's input kind.
py::dict estimate(const std::string& spec, const py::dict& inputs) {
  nlohmann::ordered_json params;
  const ConfigNode node = ConfigNode::load_string(spec, "estimator");
  const EstimatorBinding bound = estimator_registry().create(node, params);
  node.report_unused();  // a misspelt keyword fails, as in a scene
  if (bound.input == "any") throw InputError("estimator: an external program's input is set by its `input` key");
  const EstimatorInput in = input_of(bound.input, inputs);
  Estimate e;
  {
    py::gil_scoped_release free;
    e = bound.run(in);
  }
  py::dict values;
  for (const auto& [q, v] : e.values) values[quantity_name(q)] = v;
  py::dict named;
  for (const auto& [name, p] : e.points) named[name.c_str()] = vector_of(3, [&](std::size_t j) { return p[static_cast<int>(j)]; });
  py::list detections;
  for (const Detection& x : e.detections)
    detections.append(py::dict(py::arg("x") = x.circle.x, py::arg("y") = x.circle.y, py::arg("r") = x.circle.r,
                               py::arg("score") = x.score));
  py::list instances;
  for (const ImageDetection& x : e.instances) {
    py::dict d(py::arg("category") = x.category, py::arg("score") = x.score,
               py::arg("bbox") = std::vector<double>{x.x, x.y, x.w, x.h}, py::arg("volume") = x.volume);
    if (!x.mask.empty()) {
      py::array_t<std::uint8_t> m(std::vector<py::ssize_t>{x.mask_h, x.mask_w});
      std::copy(x.mask.begin(), x.mask.end(), m.mutable_data());
      d["mask"] = m;
      d["mask_origin"] = std::vector<int>{x.mask_x, x.mask_y};
    }
    instances.append(d);
  }
  py::dict d;
  d["values"] = values;
  d["points"] = named;
  d["detections"] = detections;
  d["instances"] = instances;
  d["class_scores"] = Eigen::MatrixXd(e.class_scores);
  d["watertight"] = e.watertight;
  d["error"] = e.error;
  d["notes"] = e.notes;
  d["input"] = bound.input;
  d["params_json"] = params.dump();
  return d;
}

// `cycles_cache`: the folder Cycles' images are kept in; empty: the run folder's.
// `progress`: None, or called as progress(done, total, detail, failed) after each case,
// from the worker that finished it (the GIL taken for the call; what it raises is
// reported as unraisable, the run goes on).
void run(const SceneSet& set, const std::string& out, int threads, bool quiet, const py::object& progress,
         const std::string& cycles_cache) {
  RunOptions o;
  o.out = std::filesystem::path(out) / set.base.name;
  o.threads = threads;
  o.cycles_cache = cycles_cache;
  o.verbosity = quiet ? Verbosity::quiet : Verbosity::normal;
  if (!progress.is_none()) {
    auto callback = std::shared_ptr<py::object>(new py::object(progress), [](py::object* f) {
      py::gil_scoped_acquire gil;
      delete f;
    });
    o.on_case = [callback](int done, int total, const std::string& detail, bool failed) {
      py::gil_scoped_acquire gil;
      try {
        (*callback)(done, total, detail, failed);
      } catch (py::error_already_set& e) {
        e.discard_as_unraisable("grapebench.run progress callback");
      }
    };
  }
  RunOutcome r;
  {
    py::gil_scoped_release free;
    r = run_scene_set(set, o);
  }
  if (!r.complete) throw std::runtime_error("run: not every case finished in " + o.out.string());
}

nlohmann::ordered_json key_json(const KeyInfo& k) {
  return {{"key", k.key}, {"unit", k.unit}, {"range", k.range}, {"default", k.default_value}, {"doc", k.doc},
          {"when", k.when}, {"required", k.default_value == "(required)"}};
}

// Every entry of a registry: type, summary, its key table and its typed defaults.
template <class Product>
nlohmann::ordered_json entries_json(const Registry<Product>& r) {
  nlohmann::ordered_json a = nlohmann::ordered_json::array();
  for (const auto& e : r.entries()) {
    nlohmann::ordered_json keys = nlohmann::ordered_json::array();
    for (const KeyInfo& k : e.keys()) keys.push_back(key_json(k));
    a.push_back({{"type", e.type}, {"summary", e.summary}, {"keys", keys}, {"defaults", e.defaults()}});
  }
  return a;
}

// The key tables behind the package's docstrings and type stubs (python/grapebench/_registry.py).
std::string registries_json() {
  nlohmann::ordered_json j;
  j["estimator"] = entries_json(estimator_registry());
  j["sensor"] = entries_json(sensor_registry());
  j["rig"] = entries_json(rig_registry());
  j["registration"] = entries_json(registration_registry());
  j["filter"] = entries_json(filter_registry());
  j["protocol"] = entries_json(protocol_registry());
  // A protocol's keys are the pipeline's that apply to it (`when` names it, or none).
  for (auto& p : j["protocol"]) {
    const std::string type = p["type"].get<std::string>();
    static const PipelineSpec defaults;
    for (const KeyInfo& k : pipeline_param_table().keys(defaults)) {
      if (k.when.empty() || k.when.find(type) != std::string::npos) p["keys"].push_back(key_json(k));
    }
  }
  return j.dump();
}

nlohmann::json parse_json(const std::string& text, const std::string& what) {
  try {
    return parse_json_bounded(text);
  } catch (const std::exception& e) {
    throw InputError(what + ": not JSON: " + e.what());
  }
}

// Scoring functions (bench/scoring/): the harness's own, on numpy input; results as dicts.
py::dict score_dict(const Score& s) {
  return py::dict(py::arg("cases") = s.cases, py::arg("succeeded") = s.succeeded,
                  py::arg("success_rate") = s.success_rate, py::arg("r2") = s.r2,
                  py::arg("r2_identity") = s.r2_identity, py::arg("rmse") = s.rmse, py::arg("mae") = s.mae,
                  py::arg("bias") = s.bias, py::arg("mape") = s.mape, py::arg("slope") = s.slope,
                  py::arg("intercept") = s.intercept);
}

py::dict interval(const Interval& i) { return py::dict(py::arg("lo") = i.lo, py::arg("hi") = i.hi); }

// `who`'s two inputs must have one value per case.
void same_length(std::size_t a, std::size_t b, const char* who) {
  if (a != b)
    throw InputError(std::string(who) + ": estimate has " + std::to_string(a) + " values and truth " +
                     std::to_string(b) + " (one per case each)");
}

void bind_scoring(py::module_& m) {
  m.def("score_scalars", [](const std::vector<double>& estimate, const std::vector<double>& truth) {
    same_length(estimate.size(), truth.size(), "scalars");
    std::vector<double> e, t;  // the successful rows: a finite estimate
    for (std::size_t i = 0; i < estimate.size(); ++i)
      if (std::isfinite(estimate[i])) e.push_back(estimate[i]), t.push_back(truth[i]);
    return score_dict(score(e, t, static_cast<int>(estimate.size()), {}));
  });
  m.def("bootstrap_scalars", [](const std::vector<double>& estimate, const std::vector<double>& truth,
                                std::uint64_t seed, int resamples, double level) {
    same_length(estimate.size(), truth.size(), "bootstrap");
    check_range(resamples, 10, 1e6, "bootstrap", "resamples");
    check_range(level, 0.5, 0.999, "bootstrap", "level");
    const ScoreIntervals s = bootstrap_score_intervals(estimate, truth, seed, resamples, level);
    return py::dict(py::arg("rmse") = interval(s.rmse), py::arg("bias") = interval(s.bias),
                    py::arg("mape") = interval(s.mape), py::arg("r2") = interval(s.r2));
  });
  m.def("concordance", [](const std::vector<double>& estimate, const std::vector<double>& truth) {
    same_length(estimate.size(), truth.size(), "concordance");
    return concordance(estimate, truth);
  });
  m.def("bland_altman", [](const std::vector<double>& estimate, const std::vector<double>& truth) {
    same_length(estimate.size(), truth.size(), "bland_altman");
    const Agreement a = bland_altman(estimate, truth);
    return py::dict(py::arg("mean_difference") = a.mean_difference, py::arg("lower") = a.lower,
                    py::arg("upper") = a.upper);
  });
  m.def("compare_paired", [](const std::vector<double>& a, const std::vector<double>& b, std::uint64_t seed,
                             int resamples, double level) {
    same_length(a.size(), b.size(), "compare_paired");
    check_range(resamples, 10, 1e6, "compare_paired", "resamples");
    check_range(level, 0.5, 0.999, "compare_paired", "level");
    const PairedComparison c = compare_paired(a, b, seed, resamples, level);
    return py::dict(py::arg("cases") = c.cases, py::arg("mean_difference") = c.mean_difference,
                    py::arg("interval") = interval(c.interval), py::arg("w_plus") = c.test.w_plus,
                    py::arg("p") = c.test.p);
  });
  m.def("score_points", [](const Eigen::Matrix<double, Eigen::Dynamic, 3>& estimate,
                           const Eigen::Matrix<double, Eigen::Dynamic, 3>& truth, double tolerance) {
    same_length(static_cast<std::size_t>(estimate.rows()), static_cast<std::size_t>(truth.rows()), "points");
    check_range(tolerance, 0, 1e3, "points", "tolerance", "m");
    std::vector<Vec3> e, t;
    for (Eigen::Index i = 0; i < estimate.rows(); ++i) e.emplace_back(estimate.row(i)), t.emplace_back(truth.row(i));
    const PointScore s = score_points(e, t, tolerance);
    return py::dict(py::arg("cases") = s.cases, py::arg("answered") = s.answered, py::arg("within") = s.within,
                    py::arg("success_rate") = s.success_rate, py::arg("mean_error") = s.mean_error,
                    py::arg("median_error") = s.median_error, py::arg("rmse") = s.rmse,
                    py::arg("max_error") = s.max_error, py::arg("axis_bias") = s.axis_bias,
                    py::arg("axis_rmse") = s.axis_rmse, py::arg("axis_mae") = s.axis_mae);
  });
  m.def("score_classes", [](const std::vector<int>& truth, const Eigen::MatrixXd& scores,
                            const std::vector<std::string>& classes) {
    if (static_cast<Eigen::Index>(truth.size()) != scores.rows() ||
        scores.cols() != static_cast<Eigen::Index>(classes.size()))
      throw InputError("classes: scores must be N x K (N = " + std::to_string(truth.size()) +
                       " points, K = " + std::to_string(classes.size()) + " classes), got " +
                       std::to_string(scores.rows()) + " x " + std::to_string(scores.cols()));
    for (std::size_t i = 0; i < truth.size(); ++i)
      if (truth[i] < 0 || truth[i] >= static_cast<int>(classes.size()))
        throw InputError("classes: truth[" + std::to_string(i) + "] = " + std::to_string(truth[i]) +
                         " outside [0, " + std::to_string(classes.size() - 1) + "]");
    if (!scores.allFinite()) throw InputError("classes: scores hold a non-finite value");
    const ClassScores s = score_classes(truth, scores, classes);
    py::list roc;
    for (const RocCurve& c : s.roc)
      roc.append(py::dict(py::arg("fpr") = c.fpr, py::arg("tpr") = c.tpr, py::arg("threshold") = c.threshold));
    return py::dict(py::arg("classes") = s.classes, py::arg("confusion") = Eigen::MatrixXi(s.confusion),
                    py::arg("points") = s.points, py::arg("precision") = s.precision, py::arg("recall") = s.recall,
                    py::arg("iou") = s.iou, py::arg("accuracy") = s.accuracy, py::arg("miou") = s.miou,
                    py::arg("auc") = s.auc, py::arg("roc") = roc);
  });
  m.def("score_detections", [](const Eigen::Matrix<double, Eigen::Dynamic, 4>& detections,
                               const Eigen::Matrix<double, Eigen::Dynamic, 3>& truth, const std::vector<bool>& visible,
                               const std::string& rule, double threshold) {
    if (static_cast<Eigen::Index>(visible.size()) != truth.rows())
      throw InputError("detections: visible needs one flag per truth object (" + std::to_string(truth.rows()) + ")");
    if (!detections.allFinite() || !truth.allFinite()) throw InputError("detections: a non-finite value");
    DetectionMatch match;
    if (rule == "disc_iou") match.rule = DetectionMatch::Rule::DiscIou;
    else if (rule == "centre_in_radius") match.rule = DetectionMatch::Rule::CentreInRadius;
    else throw InputError("detections: rule '" + rule + "' is not one of disc_iou, centre_in_radius");
    check_range(threshold, 0, 10, "detections", "threshold");
    match.threshold = threshold;
    std::vector<Detection> d;
    for (Eigen::Index i = 0; i < detections.rows(); ++i) {
      if (detections(i, 2) <= 0) throw InputError("detections: row " + std::to_string(i) + " has radius <= 0");
      d.push_back({{detections(i, 0), detections(i, 1), detections(i, 2)}, detections(i, 3)});
    }
    std::vector<TruthObject> t;
    for (Eigen::Index i = 0; i < truth.rows(); ++i) {
      if (truth(i, 2) <= 0) throw InputError("truth: row " + std::to_string(i) + " has radius <= 0");
      t.push_back({{truth(i, 0), truth(i, 1), truth(i, 2)}, visible[static_cast<std::size_t>(i)]});
    }
    const DetectionScore s = score_detections(d, t, match);
    return py::dict(py::arg("detections") = s.detections, py::arg("matched") = s.matched,
                    py::arg("false_positives") = s.false_positives, py::arg("visible") = s.visible,
                    py::arg("visible_found") = s.visible_found, py::arg("precision") = s.precision,
                    py::arg("recall") = s.recall, py::arg("f1") = s.f1,
                    py::arg("centre_error_mean") = s.centre_error_mean,
                    py::arg("radius_error_mean") = s.radius_error_mean,
                    py::arg("radius_error_mae") = s.radius_error_mae, py::arg("match") = s.match);
  });
  m.def("coco_evaluate", [](const std::string& ground_truth_json, const std::string& results_json,
                            const std::string& iou_type, const std::vector<int>& max_dets) {
    CocoEvalParams p;
    if (iou_type == "bbox") p.type = CocoIouType::Bbox;
    else if (iou_type == "segm") p.type = CocoIouType::Segm;
    else throw InputError("coco: iou_type '" + iou_type + "' is not one of bbox, segm");
    if (max_dets.size() != 3) throw InputError("coco: max_dets needs three limits, as COCO's summary");
    for (int d : max_dets) check_range(d, 1, 1e6, "coco", "max_dets");
    p.max_dets = max_dets;
    const CocoGroundTruth gt = read_coco_ground_truth(parse_json(ground_truth_json, "ground truth"), "ground truth");
    const std::vector<CocoObject> dets =
        read_coco_results(parse_json(results_json, "results"), "results", gt, p.type);
    CocoEvalResult r;
    {
      py::gil_scoped_release free;
      r = coco_evaluate(gt, dets, p);
    }
    py::dict stats, per;
    for (std::size_t k = 0; k < r.stats.size(); ++k) stats[coco_stat_name(k, p.max_dets).c_str()] = r.stats[k];
    for (const auto& [c, s] : r.per_category) {
      py::dict d;
      for (std::size_t k = 0; k < s.size(); ++k) d[coco_stat_name(k, p.max_dets).c_str()] = s[k];
      per[c.name.c_str()] = d;
    }
    return py::dict(py::arg("stats") = stats, py::arg("per_category") = per);
  });
  m.def("ciede2000", [](const Eigen::Vector3d& lab1, const Eigen::Vector3d& lab2) { return ciede2000(lab1, lab2); });
  m.def("srgb8_to_lab", [](int r, int g, int b) {
    for (int v : {r, g, b}) check_range(v, 0, 255, "srgb8_to_lab", "channel");
    return Eigen::Vector3d(srgb8_to_lab(static_cast<std::uint8_t>(r), static_cast<std::uint8_t>(g),
                                        static_cast<std::uint8_t>(b)));
  });
  m.def("luminance_ssim", [](const py::array_t<std::uint8_t, py::array::c_style | py::array::forcecast>& a,
                             const py::array_t<std::uint8_t, py::array::c_style | py::array::forcecast>& b) {
    if (a.ndim() != 3 || a.shape(2) != 3 || b.ndim() != 3 || b.shape(0) != a.shape(0) || b.shape(1) != a.shape(1) ||
        b.shape(2) != 3)
      throw InputError("luminance_ssim: two H x W x 3 uint8 images of one size");
    const std::vector<std::uint8_t> va(a.data(), a.data() + a.size()), vb(b.data(), b.data() + b.size());
    return luminance_ssim(va, vb, static_cast<int>(a.shape(1)), static_cast<int>(a.shape(0)));
  });
}

}  // namespace

PYBIND11_MODULE(_grapebench, m) {
  m.doc() = "grapebench's C++ core (use the `grapebench` package)";
  // Bad input (a scene key out of range, a malformed cloud): a ValueError naming the
  // file, line and key, as the command line's exit code 2.
  py::register_exception<InputError>(m, "InputError", PyExc_ValueError);

  py::class_<SceneSet>(m, "SceneSet")
      .def_property_readonly("name", [](const SceneSet& s) { return s.base.name; })
      .def_property_readonly("path", [](const SceneSet& s) { return s.base.path; })
      .def_property_readonly("seed", [](const SceneSet& s) { return s.base.seed; })
      .def_property_readonly("protocol", [](const SceneSet& s) { return s.base.protocol; })
      .def_property_readonly("conditions",
                             [](const SceneSet& s) {
                               std::vector<std::string> labels;
                               for (const Condition& c : s.conditions) labels.push_back(c.label);
                               return labels;
                             })
      .def_property_readonly("bunch_count", [](const SceneSet& s) { return bunch_jobs(s.base).size(); })
      .def("scene_json", [](const SceneSet& s) { return scene_json(s.base).dump(); });

  m.def("parse_scene_set", &parse_scene_set, py::arg("text"), py::arg("name"));
  m.def("load_scene_set", &load_scene_set, py::arg("path"));
  m.def("synth_bunch", &synth_bunch, py::arg("scene"), py::arg("index"), py::arg("mesh") = false);
  m.def("scan_bunch", &scan_of, py::arg("scene"), py::arg("index"));
  m.def("registries_json", &registries_json);
  bind_scoring(m);
  m.def("estimator_types", [] { return estimator_registry().types(); });
  m.def("estimate", &estimate, py::arg("spec"), py::arg("inputs"));
  m.def("run", &run, py::arg("scene"), py::arg("out"), py::arg("threads"), py::arg("quiet"),
        py::arg("progress") = py::none(), py::arg("cycles_cache") = "");
}
