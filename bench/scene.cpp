#include "bench/scene.h"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "synth/rng.h"

namespace grapebench {

namespace {

std::vector<std::pair<std::string, std::string>> names(const std::vector<std::string>& list) {
  std::vector<std::pair<std::string, std::string>> out;
  for (const auto& s : list) out.emplace_back(s, s);
  return out;
}

bool single_frame(const PipelineSpec& p) { return p.protocol == "single_frame"; }
bool multi_view(const PipelineSpec& p) { return p.protocol == "multi_view"; }
bool stereo_pair(const PipelineSpec& p) { return p.protocol == "stereo_pair"; }
bool classification(const PipelineSpec& p) { return p.protocol == "classification"; }
bool detection(const PipelineSpec& p) { return p.protocol == "detection"; }
bool point_cloud(const PipelineSpec& p) { return multi_view(p) || single_frame(p); }

nlohmann::ordered_json steps_json(const std::vector<FilterSpec>& list) {
  nlohmann::ordered_json a = nlohmann::ordered_json::array();
  for (const auto& f : list) a.push_back(f.params);
  return a;
}

}  // namespace

const ParamTable<PipelineSpec>& pipeline_param_table() {
  using P = PipelineSpec;
  static const ParamTable<P> table =
      ParamTable<P>()
          .choice("segmentation", &P::segmentation,
                  {{"labels", P::Segmentation::Labels}, {"none", P::Segmentation::None}},
                  "labels: the returns on bunch parts (an oracle); none: every return, view_filters must find the "
                  "bunch (single_frame: none only)")
          .when("protocol: multi_view or single_frame", point_cloud)
          .real("min_points", "count", &P::min_points, 4, 1e9, "a case with fewer bunch points fails")
          .when("protocol: multi_view", multi_view)
          .real("visibility_hull", "m", &P::visibility_hull, 0, 0.05,
                "0 off; else the step of the rig's visibility hull, a volume row `visibility_hull` (the floor)")
          .when("protocol: multi_view", multi_view)
          .choice_list("rois", &P::rois, names({"auto_r", "auto_cm", "manual_r", "manual_cm"}), 1,
                       "ROI kinds measured (seed 003: ROI_R^A, ROI_CM^A, ROI_R^M, ROI_CM^M)")
          .when("protocol: single_frame", single_frame)
          .section("roi", &P::roi, seed003_roi_param_table(), "seed 003's detection and ROI (Sect. II-B)")
          .when("protocol: single_frame", single_frame)
          .boolean("fine_tune", &P::fine_tune, "the fine-tuning step on every ROI (seed 003)")
          .when("protocol: single_frame", single_frame)
          .integer("manual_min_berry_points", "count", &P::manual_min_berry_points, 1, 100000000,
                   "fewer visible berry returns: no manual label")
          .when("protocol: single_frame", single_frame)
          .real("cut_tolerance", "px", &P::cut_tolerance, 0, 50,
                "a cutting point within this of a peduncle pixel of the exact label image is a success (seed 001 "
                "Sect. 3.1 counts any point on the peduncle)")
          .when("protocol: stereo_pair", stereo_pair)
          .real("berry_visible_fraction", "-", &P::berry_visible_fraction, 0, 1,
                "a berry counts as visible when this fraction of its projected disc is unoccluded in the left label "
                "image (seed 001 Table 1: occluded by less than 1/3)")
          .when("protocol: stereo_pair", stereo_pair)
          .choice("oracle", &P::oracle,
                  {{"none", P::Oracle::None}, {"cluster", P::Oracle::Cluster}, {"berries", P::Oracle::Berries},
                   {"both", P::Oracle::Both}},
                  "an ablation, never a result: the estimator is given the exact cluster pixels (in place of its "
                  "segmentation), the berries' outlines drawn from the exact labels (in place of the image its berry "
                  "stage reads), or both; rows say 'oracle: ...' in their notes (issue 38 item 7)")
          .when("protocol: stereo_pair", stereo_pair)
          .choice("reconstruction", &P::reconstruction,
                  {{"noise_model", P::Reconstruction::NoiseModel}, {"sgbm", P::Reconstruction::Sgbm}},
                  "the pass's views to points (seed 004's Bundler + PMVS stand-ins): the ray-cast returns with the "
                  "stereo depth error, or OpenCV's StereoSGBM on each view's rendered colour pair (sensor stereo_rgb)")
          .when("protocol: classification", classification)
          .section("noise_model", &P::noise_model, mvs_noise_param_table(), "the depth error of the fast path")
          .when("reconstruction: noise_model",
                [](const P& p) { return classification(p) && p.reconstruction == P::Reconstruction::NoiseModel; })
          .section("sgbm", &P::sgbm, sgbm_param_table(), "semi-global matching and its left-right check")
          .when("reconstruction: sgbm",
                [](const P& p) { return classification(p) && p.reconstruction == P::Reconstruction::Sgbm; })
          .section("fusion", &P::fusion, fusion_param_table(),
                   "the views' points to one cloud on a voxel grid, with multi-view consistency")
          .when("protocol: classification", classification)
          .choice("poses", &P::poses, {{"true", P::Poses::True}, {"colmap", P::Poses::Colmap}},
                  "the views' poses in the back-projection: the rig's, or COLMAP's sparse SfM from the images (seed "
                  "004 Sect. 3.1: Bundler), similarity-fitted to the true camera centres")
          .when("protocol: classification", classification)
          .section("colmap", &P::colmap, colmap_param_table(), "COLMAP's run (CPU: SIFT, sequential matching, mapper)")
          .when("poses: colmap", [](const P& p) { return classification(p) && p.poses == P::Poses::Colmap; })
          .real("pose_rotation_sd", "deg", &P::pose_rotation_sd, 0, 30,
                "error of each view's pose: normal rotation angle about a random axis (0: the true poses)")
          .when("poses: true", [](const P& p) { return classification(p) && p.poses == P::Poses::True; })
          .real("pose_translation_sd", "m", &P::pose_translation_sd, 0, 1,
                "error of each view's pose: normal translation per axis (0: the true poses)")
          .when("poses: true", [](const P& p) { return classification(p) && p.poses == P::Poses::True; })
          .choice_list("categories", &P::categories, names({"bunch", "berry", "stalk", "leaf", "cane"}), 1,
                       "categories scored (bench/image_truth.h): ground truth of the others is not annotated and "
                       "answers in them are dropped")
          .when("protocol: detection", detection)
          .integer("min_pixels", "px", &P::min_pixels, 1, 1000000,
                   "a ground-truth instance needs this many visible pixels (Helios drops objects under 10 px)")
          .when("protocol: detection", detection)
          .integer("max_detections", "count", &P::max_detections, 10, 100000,
                   "COCO's maxDets per image and category: the best-scored answers kept for AP and AR_max (COCO: 100; "
                   "a bunch holds 100-200 berries, so berries need more)")
          .when("protocol: detection", detection)
          .real("volume_match_iou", "-", &P::volume_match_iou, 0.1, 1,
                "an answered bunch with a volume is paired with the unpaired true bunch of highest mask IoU at or "
                "above this (COCO's AP50 rule), for the volume rows")
          .when("protocol: detection", detection)
          .real("split_gap", "m", &P::split_gap, 0, 10,
                "gap along the row between the training part (x below) and the test part (x above); at least twice "
                "the largest feature or CRF radius, so no neighbourhood is shared (seed 004 Sect. 4.2)")
          .when("protocol: classification", classification)
          .validate([](const P& p, const ConfigNode& n) {
            if (single_frame(p) && p.segmentation != P::Segmentation::None) {
              n.fail("segmentation",
                     "the single_frame protocol measures every return of a frame (seed 003): only none");
            }
            if (p.visibility_hull > 0 && p.visibility_hull < 1e-4) {
              n.fail("visibility_hull", "must be 0 (off) or lie in [1e-4, 0.05] m");
            }
          });
  return table;
}

nlohmann::ordered_json PipelineSpec::describe() const {
  nlohmann::ordered_json j = pipeline_param_table().to_json(*this);
  if (multi_view(*this)) j["registration"] = registration.params;
  if (point_cloud(*this)) j["view_filters"] = steps_json(view_filters);
  if (multi_view(*this)) j["cloud_filters"] = steps_json(cloud_filters);
  return j;
}

PipelineSpec pipeline_defaults(const std::string& protocol) {
  PipelineSpec p;
  p.protocol = protocol;
  if (single_frame(p)) p.segmentation = PipelineSpec::Segmentation::None;
  p.registration.run = registration_registry().make(p.registration.type, &p.registration.params);
  return p;
}

namespace {

// `registration: name` (its defaults) or `registration: {type: name, keys...}`.
RegistrationSpec read_registration(const ConfigNode& n) {
  RegistrationSpec r;
  if (n.yaml()["registration"].IsMap()) {
    r.run = registration_registry().create(n.child("registration"), r.params);
    r.type = r.params["type"].get<std::string>();
  } else {
    r.type = n.get_choice("registration", r.type, registration_registry().types());
    r.run = registration_registry().make(r.type, &r.params);
  }
  return r;
}

}  // namespace

PipelineSpec read_pipeline(const ConfigNode& n, const std::string& protocol) {
  PipelineSpec p = pipeline_defaults(protocol);
  pipeline_param_table().read(n, p);
  if (n.has("registration")) {
    if (!multi_view(p)) n.fail("registration", "is read only with protocol: multi_view");
    p.registration = read_registration(n);
  }
  for (const char* list : {"view_filters", "cloud_filters"}) {
    if (!n.has(list)) continue;
    for (const auto& f : n.children(list)) {
      FilterSpec spec;
      spec.run = filter_registry().create(f, spec.params);
      spec.type = spec.params["type"].get<std::string>();
      (list == std::string("view_filters") ? p.view_filters : p.cloud_filters).push_back(std::move(spec));
    }
  }
  if (n.has("view_filters") && stereo_pair(p)) {
    n.fail("view_filters", "is read only with a point-cloud protocol (multi_view, single_frame)");
  }
  if (n.has("cloud_filters") && !multi_view(p)) {
    n.fail("cloud_filters", "is read only with protocol: multi_view (a registered cloud); use view_filters");
  }
  return p;
}

std::vector<EstimatorSpec> read_estimators(const ConfigNode& root) {
  std::vector<EstimatorSpec> out;
  const auto list = root.children("estimators");
  // Issue 39: 10,000 estimators ran past 30 s and 1,000 took 1.2 GB before any case
  // started; scenes/ has 9 at most. A sweep multiplies scenes, not this.
  constexpr std::size_t kMaxEstimators = 256;
  if (list.size() > kMaxEstimators)
    root.fail("estimators", "a list of " + std::to_string(list.size()) + " estimators; at most " +
                                std::to_string(kMaxEstimators) + " per scene (split the scene)");
  for (const auto& n : list) {
    EstimatorSpec e;
    EstimatorBinding bound = estimator_registry().create(n, e.params);
    e.type = e.params["type"].get<std::string>();
    e.quantities = std::move(bound.quantities);
    e.input = bound.input;
    e.run = std::move(bound.run);
    e.name = n.get_string("name", e.type);
    e.time_budget = n.get_real("time_budget", e.time_budget, 0.001, 86400);
    e.memory_budget = n.get_real("memory_budget", e.memory_budget, 1, 1e7);
    if (e.name.empty() || e.name.find_first_of(",\"\n ") != std::string::npos) {
      n.fail("name", "must be non-empty without spaces, commas or quotes");
    }
    if (e.name == "visibility_hull")
      n.fail("name", "'visibility_hull' is reserved for the rig's floor row (pipeline.visibility_hull); pick another");
    for (const auto& other : out) {
      if (other.name == e.name) n.fail("name", "'" + e.name + "' is used twice; give each estimator its own `name:`");
    }
    out.push_back(std::move(e));
  }
  if (root.has("estimators") && out.empty()) root.fail("estimators", "the list is empty");
  return out;
}

std::string registration_label(const Scene& scene) {
  return scene.protocol == "multi_view" ? scene.pipeline.registration.type : scene.protocol;
}

const ParamTable<DatasetParams>& dataset_param_table() {
  using P = DatasetParams;
  static const ParamTable<P> table =
      ParamTable<P>()
          .real("train", "-", &P::train, 0, 1,
                "fraction of the bunch seeds whose views go to the training split (hashed from the seed, so "
                "a bunch's views and its sweep conditions share one split)")
          .real("val", "-", &P::val, 0, 1, "fraction in the validation split; the rest is the test split")
          .integer("min_pixels", "px", &P::min_pixels, 1, 1000000,
                   "visible pixels an instance needs to be annotated (Helios drops objects under 10 px; 1 keeps "
                   "every visible one)")
          .boolean("float_depth", &P::float_depth,
                   "also write depth as 32-bit float TIFF in m (OpenCV 4.6 writes it uncompressed: 11 MB at "
                   "2048 x 1365; the 16-bit PNG in mm is always written)")
          .validate([](const P& p, const ConfigNode& node) {
            if (p.train + p.val > 1 + 1e-12)
              node.fail("val", "train + val is " + std::to_string(p.train + p.val) + ", at most 1");
          });
  return table;
}

RayScene scene_rays(const Scene& scene, const Bunch& bunch, std::uint64_t bunch_seed) {
  if (!scene.foliage) return RayScene(bunch);
  return RayScene(bunch, std::nullopt, generate_foliage(*scene.foliage, bunch, derive_seed(bunch_seed, 0x1eaf)));
}

nlohmann::ordered_json scene_json(const Scene& s) {
  nlohmann::ordered_json j;
  j["name"] = s.name;
  j["seed"] = s.seed;
  nlohmann::ordered_json groups = nlohmann::ordered_json::array();
  for (const auto& g : s.groups) {
    nlohmann::ordered_json group = {{"preset", g.preset}, {"count", g.count}};
    const nlohmann::ordered_json params = bunch_param_table().to_json(g.params);
    for (const auto& [k, v] : params.items()) group[k] = v;
    groups.push_back(group);
  }
  j["bunches"] = groups;
  if (s.sensor) j["sensor"] = s.sensor->describe();
  if (s.rig) j["rig"] = s.rig->describe();
  j["background"] = background_param_table().to_json(s.background);
  if (s.foliage) j["foliage"] = foliage_param_table().to_json(*s.foliage);
  if (s.vine_row) j["vine_row"] = vine_row_param_table().to_json(*s.vine_row);
  j["dataset"] = dataset_param_table().to_json(s.dataset);
  j["pipeline"] = s.pipeline.describe();
  j["protocol"] = s.protocol;
  if (!s.estimators.empty()) {
    nlohmann::ordered_json est = nlohmann::ordered_json::array();
    for (const auto& e : s.estimators) {
      nlohmann::ordered_json one = {{"name", e.name}};
      for (const auto& [k, v] : e.params.items()) one[k] = v;
      one["time_budget"] = e.time_budget;
      one["memory_budget"] = e.memory_budget;
      est.push_back(one);
    }
    j["estimators"] = est;
  }
  return j;
}

std::vector<BunchJob> bunch_jobs(const Scene& scene) {
  std::vector<BunchJob> jobs;
  for (const auto& g : scene.groups) {
    for (int k = 0; k < g.count; ++k) {
      const int index = static_cast<int>(jobs.size());
      jobs.push_back({g.preset, index, derive_seed(scene.seed, static_cast<std::uint64_t>(index)), g.params});
    }
  }
  return jobs;
}

}  // namespace grapebench
