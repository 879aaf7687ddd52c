// Scene files: the strict YAML documents `grapebench` runs (see scenes/README.md).
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "algorithms/cloud/registration.h"
#include "algorithms/registry.h"
#include "algorithms/segmentation/seed003_roi.h"
#include "bench/protocols/registration_methods.h"
#include "sensors/rig.h"
#include "sensors/sensor_registry.h"
#include "algorithms/stereo/colmap_sfm.h"
#include "algorithms/stereo/sgbm_reconstruction.h"
#include "sensors/mvs_reconstruction.h"
#include "synth/foliage.h"
#include "synth/vine_row.h"
#include "synth/params.h"

namespace grapebench {

struct BunchGroup {
  std::string preset;
  int count = 1;
  BunchParams params;  // the preset with the scene's overrides applied
};

// One registered pipeline step with its parameters (defaults filled): {type, keys...}.
struct FilterSpec {
  std::string type;
  nlohmann::ordered_json params;
  BoundFilter run;
};

// A registration method with its parameters (scene `pipeline.registration`: a name,
// or {type: name, keys...}).
struct RegistrationSpec {
  std::string type = "true_poses";
  nlohmann::ordered_json params;  // {type, every key with its value}
  RegistrationMethod run;
};

// How the views of a scan become one bunch cloud (scene section `pipeline:`):
// segmentation, view_filters on each view (camera frame), registration, then
// cloud_filters on the registered cloud.
struct PipelineSpec {
  // labels: keep the returns whose ground-truth label is a bunch part (an oracle
  // segmentation, so registration and estimators are scored alone); none: keep every
  // return, so view_filters (pass_through, region_growing...) must find the bunch.
  enum class Segmentation { Labels, None };
  Segmentation segmentation = Segmentation::Labels;
  const char* segmentation_name() const { return segmentation == Segmentation::Labels ? "labels" : "none"; }
  std::vector<FilterSpec> view_filters;
  std::vector<FilterSpec> cloud_filters;
  // multi_view: a registered method (bench/protocols/registration_methods.h) with its
  // keys. The single_frame protocol (seed 003) registers nothing: every view is
  // measured alone: its returns go through view_filters (the pass-through), then each
  // ROI of `rois` is fine-tuned and the estimators run on it (rows per frame and ROI).
  RegistrationSpec registration;
  // The scene's protocol (context for which keys apply; not a key of `pipeline:`).
  std::string protocol = "multi_view";
  // single_frame: auto_r (ROI_R^A), auto_cm (ROI_CM from it, Eq. 2), manual_r (ROI_R^M:
  // the annotator's region, here perfect: the returns labelled berry, pedicel or
  // rachis), manual_cm.
  std::vector<std::string> rois{"auto_r", "auto_cm", "manual_r", "manual_cm"};
  Seed003RoiParams roi;
  bool fine_tune = true;              // single_frame: the fine-tuning step on every ROI
  int manual_min_berry_points = 100;  // single_frame: fewer visible berry returns, no label, [1, 1e8]
  // stereo_pair (seed 001): a cutting point within cut_tolerance px of a peduncle pixel
  // of the exact left label image is a success; a berry is visible when at least
  // berry_visible_fraction of its projected disc is unoccluded there (Table 1: 2/3).
  double cut_tolerance = 2;
  double berry_visible_fraction = 2.0 / 3.0;
  // stereo_pair's oracle ablation (EstimatorInput::oracle): stages of the estimator
  // given the exact answer from the left label image, so a gap is traced to its stage.
  enum class Oracle { None, Cluster, Berries, Both };
  Oracle oracle = Oracle::None;
  const char* oracle_name() const {
    return oracle == Oracle::Cluster ? "cluster" : oracle == Oracle::Berries ? "berries" : oracle == Oracle::Both ? "both" : "none";
  }
  // classification (seed 004): how the pass becomes one coloured cloud (noise_model: the
  // ray-cast returns with the stereo depth error; sgbm: semi-global matching of each
  // view's rendered colour pair), the fusion of the views, and the gap (m) along the
  // row between the training part (x below it) and the test part.
  enum class Reconstruction { NoiseModel, Sgbm };
  Reconstruction reconstruction = Reconstruction::NoiseModel;
  MvsNoiseParams noise_model;
  SgbmParams sgbm;
  FusionParams fusion;
  // Each view's pose in the back-projection: the true one moved by a random rotation
  // (normal angle of this sd about a random axis) and translation (normal per axis).
  // true: the rig's poses (perturbed as below); colmap: estimated from the views'
  // colour images by COLMAP's sparse SfM, brought to metric scale by a similarity fit of
  // its camera centres to the true ones (Umeyama), then scored against the true poses.
  enum class Poses { True, Colmap };
  Poses poses = Poses::True;
  ColmapParams colmap;
  double pose_rotation_sd = 0;     // deg, [0, 30]
  double pose_translation_sd = 0;  // m, [0, 1]
  double split_gap = 0.3;
  // detection: the categories scored (kDatasetCategories' names), the fewest visible
  // pixels of a ground-truth instance, and the mask IoU at which a bunch answer with a
  // volume is paired with a true bunch for the volume rows.
  std::vector<std::string> categories{"bunch", "berry"};
  int min_pixels = 1;
  double volume_match_iou = 0.5;
  int max_detections = 100;  // COCO's maxDets: the last of its three limits (1, 10, this)
  double min_points = 100;  // a case with fewer bunch points fails, [4, 1e9]
  // m, sample step of the rig's visibility hull (sensors/visibility_hull.h), reported
  // as the volume row of the reference `visibility_hull`: the floor of any estimator
  // that invents no geometry. 0: off (the default); else [1e-4, 0.05].
  double visibility_hull = 0;
  // Every key that applies, as a `pipeline:` section that reads back as this spec.
  nlohmann::ordered_json describe() const;
};
// The keys of `pipeline:` other than the step lists.
const ParamTable<PipelineSpec>& pipeline_param_table();

struct EstimatorSpec {
  std::string name;  // column name in the results (default: the type)
  std::string type;
  std::vector<Quantity> quantities;
  std::string input = "cloud";    // cloud | stereo_pair (EstimatorBinding::input)
  nlohmann::ordered_json params;  // {type, every parameter with defaults filled}
  BoundEstimator run;
  // Budget of one run (keys of every entry; bench/heap_meter.h): past it the row
  // fails with the reason. Safe defaults: no built-in estimator needs a tenth of them
  // on the papers' bunches.
  double time_budget = 600;     // s, wall, [0.001, 86400]
  double memory_budget = 8192;  // MB of heap held at once, [1, 1e7]
};

// One swept parameter: a dotted path into the scene ("sensor.noise_scale",
// "bunches.compactness" for every group, "estimators[1].alpha") and its values.
// A list of strings ("background.type: [none, cloth]") sweeps names: `names` holds
// them and `values` their positions 0, 1, ...
struct SweepAxis {
  std::string key;
  std::vector<double> values;
  std::vector<std::string> names;  // empty for a numeric axis
};

// The labelled image datasets of `grapebench dataset` (bench/dataset_run.h): which
// bunches go to which split, and which instances are annotated.
struct DatasetParams {
  double train = 0.7;   // fraction of the cases' bunch seeds in the training split, [0, 1]
  double val = 0.15;    // in the validation split (the rest: test), [0, 1]
  int min_pixels = 1;   // visible pixels an instance needs to be annotated, [1, 1000000]
  bool float_depth = true;  // also the float TIFF depth (m): 4 bytes a pixel, uncompressed
};
const ParamTable<DatasetParams>& dataset_param_table();  // scene section `dataset:`

struct Scene {
  std::string path;
  std::string name;
  std::uint64_t seed = 0;
  // The registered protocol a case runs (bench/protocols/): multi_view (seeds 000, 002)
  // or single_frame (seed 003).
  std::string protocol = "multi_view";
  std::vector<BunchGroup> groups;
  // Capture (optional sections `sensor`, `rig`, `background`); built while parsing so
  // their errors name file:line before any work starts.
  std::shared_ptr<const Sensor> sensor;
  std::shared_ptr<const Rig> rig;
  BackgroundSpec background;
  // Leaves and canes around each bunch (section `foliage:`, the vine-row scene).
  std::optional<FoliageParams> foliage;
  // The vine-row section of protocol classification (section `vine_row:`, seed 004).
  std::optional<VineRowParams> vine_row;
  // What `grapebench dataset` writes (section `dataset:`; its defaults without one).
  DatasetParams dataset;
  PipelineSpec pipeline;
  std::vector<EstimatorSpec> estimators;
  std::vector<SweepAxis> sweep;  // as written; each Condition below is one point
};

// One point of a scene's sweep: the scene with the swept values substituted.
struct Condition {
  std::vector<double> values;  // one per sweep axis
  std::string label;           // "noise_scale=0.5 distance=1" ("" without sweep)
  Scene scene;
};

// A scene file and its conditions (one when it has no `sweep:`).
struct SceneSet {
  Scene base;
  std::vector<Condition> conditions;
};

// One bunch to generate: its own seed is derived from the scene seed and its index,
// so bunches can be produced in any order on any number of threads.
struct BunchJob {
  std::string preset;
  int index = 0;
  std::uint64_t seed = 0;
  BunchParams params;
};

// Section readers (bench/scene_file.h reads whole files). Errors name file:line, key
// and allowed range.
PipelineSpec read_pipeline(const ConfigNode& node, const std::string& protocol);
// The pipeline of a scene without a `pipeline:` section.
PipelineSpec pipeline_defaults(const std::string& protocol);
// What brought the views together, for tables: the registration method, or the
// protocol's name where it registers nothing (single_frame).
std::string registration_label(const Scene& scene);
// The `estimators:` list of the scene's root mapping.
std::vector<EstimatorSpec> read_estimators(const ConfigNode& root);
std::vector<BunchJob> bunch_jobs(const Scene& scene);
// The ray scene of one bunch of `scene`: the bunch, and its foliage when the scene has
// a `foliage:` section (drawn from the bunch's seed, its own stream).
RayScene scene_rays(const Scene& scene, const Bunch& bunch, std::uint64_t bunch_seed);
// The scene as a document that reads back as the same scene (every key with its value,
// defaults filled, sweep expanded): the manifest's record and the case key's input.
nlohmann::ordered_json scene_json(const Scene& s);

}  // namespace grapebench
