#include "bench/case_result.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

#include "bench/build_info.h"
#include "synth/fnv1a.h"
#include "bench/heap_meter.h"
#include "synth/io.h"
#include "synth/utf8.h"

namespace grapebench {

namespace {

// Bump when the meaning of a case file changes, so old results are recomputed.
constexpr const char* kCaseFormat = "grapebench-case-8";

double truth_of(Quantity q, const GroundTruth& gt) {
  switch (q) {
    case Quantity::Volume:
      return gt.volume.solid;
    case Quantity::Height:
      return gt.pca_extent(0);
    case Quantity::Length:
      return gt.pca_extent(1);
    case Quantity::Width:
      return gt.pca_extent(2);
    case Quantity::PerimeterH:
      return gt.section_perimeter(0);
    case Quantity::PerimeterL:
      return gt.section_perimeter(1);
    case Quantity::PerimeterW:
      return gt.section_perimeter(2);
    // Seed 003: the hanging bunch's length and width, larger first.
    case Quantity::SizeMajor:
      return std::max(gt.height, gt.row_width);
    case Quantity::SizeMinor:
      return std::min(gt.height, gt.row_width);
    case Quantity::HangingHeight:
      return gt.height;
    case Quantity::MaxDiameter:
      return gt.max_diameter;
  }
  return 0;
}

}  // namespace

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

std::string case_key(const Condition& condition, const BunchJob& job) {
  nlohmann::ordered_json j = scene_json(condition.scene);
  j["format"] = kCaseFormat;
  j["job"] = {{"preset", job.preset}, {"index", job.index}, {"seed", job.seed}, {"params", params_json(job.params)}};
  char hex[17];
  std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(fnv1a(j.dump())));
  return hex;
}

CaseResult new_case(const Condition& condition, int condition_index, const BunchJob& job) {
  CaseResult r;
  r.condition = condition_index;
  r.bunch = job.index;
  r.preset = job.preset;
  r.seed = job.seed;
  r.key = case_key(condition, job);
  r.build = build_identity();
  return r;
}

TimedEstimate run_estimator(const EstimatorSpec& spec, const EstimatorInput& input) {
  TimedEstimate t;
  const auto t0 = std::chrono::steady_clock::now();
  // The exception is kept, not its message: after a budget's stop nothing inside the
  // run may allocate.
  std::exception_ptr error;
  const MeteredRun m = run_metered(
      [&] {
        try {
          t.estimate = spec.run(input);
        } catch (...) {
          error = std::current_exception();
        }
      },
      RunBudget{spec.time_budget, spec.memory_budget});
  t.seconds = seconds_since(t0);
  if (m.peak_bytes >= 0) t.peak_heap_mb = static_cast<double>(m.peak_bytes) / 1e6;
  if (error) {
    try {
      std::rethrow_exception(error);
    } catch (const std::exception& e) {
      t.error = escape_invalid_utf8(e.what());  // a program's bytes may be quoted
    } catch (...) {
      t.error = "an exception that is not a std::exception";
    }
  }
  char why[160];
  if (m.over_time) {
    std::snprintf(why, sizeof why, "over its time budget of %g s (time_budget)", spec.time_budget);
    t.error = why;
  } else if (m.over_memory) {
    std::snprintf(why, sizeof why, "over its memory budget of %g MB (memory_budget)", spec.memory_budget);
    t.error = why;
  }
  if (!t.error.empty()) t.estimate = Estimate{};
  return t;
}

EstimateRow estimate_row(const EstimatorSpec& spec, const TimedEstimate& t) {
  EstimateRow row;
  row.estimator = spec.name;
  row.type = spec.type;
  row.seconds = t.seconds;
  row.peak_heap_mb = t.peak_heap_mb;
  row.error = t.error;
  if (t.error.empty()) {
    row.watertight = t.estimate.watertight;
    row.notes = t.estimate.notes;
  }
  return row;
}

std::vector<EstimateRow> scalar_rows(const EstimatorSpec& spec, const TimedEstimate& t, const GroundTruth& gt,
                                     std::size_t input_points) {
  std::vector<EstimateRow> rows;
  for (const Quantity q : spec.quantities) {
    EstimateRow row = estimate_row(spec, t);
    row.quantity = quantity_name(q);
    row.truth = truth_of(q, gt);  // zero when the case failed before its ground truth
    row.region_points = input_points;
    if (row.error.empty()) {
      for (const auto& [qq, v] : t.estimate.values) {
        if (qq == q) {
          row.estimate = v;
          row.ok = std::isfinite(v);
        }
      }
      if (!row.ok) row.error = t.estimate.error.empty() ? "the estimator gave no finite value" : t.estimate.error;
    }
    rows.push_back(row);
  }
  return rows;
}

std::vector<EstimateRow> run_estimators(const std::vector<EstimatorSpec>& specs, const EstimatorInput& input,
                                        const GroundTruth& gt, const std::string& cloud_error) {
  std::vector<EstimateRow> rows;
  for (const auto& spec : specs) {
    TimedEstimate t;
    t.error = cloud_error;
    if (cloud_error.empty()) t = run_estimator(spec, input);
    for (EstimateRow& row : scalar_rows(spec, t, gt, static_cast<std::size_t>(input.points.rows()))) {
      rows.push_back(std::move(row));
    }
  }
  return rows;
}

nlohmann::ordered_json case_to_json(const CaseResult& c) {
  nlohmann::ordered_json j;
  j["format"] = kCaseFormat;
  j["key"] = c.key;
  j["build"] = c.build;
  j["condition"] = c.condition;
  j["bunch"] = c.bunch;
  j["preset"] = c.preset;
  j["seed"] = c.seed;
  j["ok"] = c.ok;
  j["error"] = c.error;
  j["points"] = c.points;
  j["views"] = c.views;
  j["rotation_error_mean_deg"] = c.rotation_error_mean_deg;
  j["rotation_error_max_deg"] = c.rotation_error_max_deg;
  j["translation_error_mean_mm"] = c.translation_error_mean_mm;
  j["translation_error_max_mm"] = c.translation_error_max_mm;
  j["scan_seconds"] = c.scan_seconds;
  j["registration_seconds"] = c.registration_seconds;
  j["segmentation_precision"] = c.segmentation_precision;
  j["segmentation_recall"] = c.segmentation_recall;
  j["peduncle_kept"] = c.peduncle_kept;
  j["body_kept"] = c.body_kept;
  j["segmentation_seconds"] = c.segmentation_seconds;
  j["filter_seconds"] = c.filter_seconds;
  nlohmann::ordered_json rows = nlohmann::ordered_json::array();
  for (const auto& r : c.rows) {
    rows.push_back({{"estimator", r.estimator},
                    {"type", r.type},
                    {"quantity", r.quantity},
                    {"ok", r.ok},
                    {"estimate", r.estimate},
                    {"truth", r.truth},
                    {"watertight", r.watertight},
                    {"error", r.error},
                    {"seconds", r.seconds},
                    {"peak_heap_mb", r.peak_heap_mb},
                    {"frame", r.frame},
                    {"roi", r.roi},
                    {"region", r.region},
                    {"region_points", r.region_points},
                    {"region_precision", r.region_precision},
                    {"notes", r.notes}});
  }
  j["rows"] = rows;
  if (!c.preview_points.empty()) {
    std::vector<float> flat;
    for (const auto& p : c.preview_points) flat.insert(flat.end(), p.begin(), p.end());
    j["preview_points_mm"] = flat;
  }
  if (c.disparity_error_px >= 0) j["disparity_error_px"] = c.disparity_error_px;
  if (c.disparity_outliers >= 0) j["disparity_outliers"] = c.disparity_outliers;
  if (!c.disparity_error_correlation.empty()) j["disparity_error_correlation"] = c.disparity_error_correlation;
  if (c.disparity_fattening >= 0) j["disparity_fattening"] = c.disparity_fattening;
  if (!c.matched_fraction.empty()) j["matched_fraction"] = c.matched_fraction;
  if (std::isfinite(c.disparity_locking)) j["disparity_locking"] = c.disparity_locking;
  if (!c.disparity_bias.empty()) j["disparity_bias"] = c.disparity_bias;
  if (!c.pixel_noise_dn.empty()) j["pixel_noise_dn"] = c.pixel_noise_dn;  // NaN written as null
  if (c.views_registered >= 0) j["views_registered"] = c.views_registered;
  if (!c.confusion.empty()) {
    nlohmann::ordered_json conf = nlohmann::ordered_json::array();
    for (const ConfusionCounts& m : c.confusion)
      conf.push_back({{"estimator", m.estimator}, {"classes", m.classes}, {"counts", m.counts}});
    j["confusion"] = conf;
  }
  if (!c.roc.empty()) {
    nlohmann::ordered_json roc = nlohmann::ordered_json::array();
    for (const RocSamples& s : c.roc) roc.push_back({{"estimator", s.estimator}, {"class", s.class_name}, {"tpr", s.tpr}});
    j["roc"] = roc;
  }
  if (!c.detection.empty()) {
    auto objects = [](const std::vector<CocoObject>& list) {
      nlohmann::ordered_json a = nlohmann::ordered_json::array();
      for (const CocoObject& o : list)
        a.push_back({{"c", o.category_id}, {"s", o.score}, {"b", o.bbox}, {"a", o.area}, {"m", rle_string(*o.mask)}});
      return a;
    };
    nlohmann::ordered_json views = nlohmann::ordered_json::array();
    for (const DetectionView& v : c.detection) {
      nlohmann::ordered_json answers = nlohmann::ordered_json::array();
      for (const auto& [name, list] : v.answers) answers.push_back({{"estimator", name}, {"instances", objects(list)}});
      views.push_back({{"view", v.view}, {"station", v.station}, {"width", v.width}, {"height", v.height},
                       {"truth", objects(v.truth)}, {"answers", answers}});
    }
    j["detection"] = views;
  }
  j["digest"] = case_digest(nlohmann::json(j));
  return j;
}

std::string case_digest(const nlohmann::json& j) {
  nlohmann::json content = j;
  content.erase("digest");
  char hex[17];
  std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(fnv1a(content.dump())));
  return hex;
}

namespace {

// A number of the case file, finite and within [lo, hi].
double checked(const nlohmann::json& j, const char* key, double lo, double hi) {
  const double v = j.at(key).get<double>();
  if (!(v >= lo && v <= hi)) throw std::runtime_error(std::string("'") + key + "' out of range");
  return v;
}

}  // namespace

CaseResult case_from_json(const nlohmann::json& j) {
  if (!j.is_object() || j.value("format", "") != kCaseFormat) throw std::runtime_error("case file of another format");
  if (!j.contains("digest") || !j["digest"].is_string() || j["digest"].get<std::string>() != case_digest(j))
    throw CaseDigestMismatch();
  CaseResult c;
  c.key = j.at("key").get<std::string>();
  c.build = j.at("build").get<std::string>();
  c.condition = j.at("condition").get<int>();
  c.bunch = j.at("bunch").get<int>();
  c.preset = j.at("preset").get<std::string>();
  c.seed = j.at("seed").get<std::uint64_t>();
  c.ok = j.at("ok").get<bool>();
  c.error = j.at("error").get<std::string>();
  c.points = j.at("points").get<std::size_t>();
  c.views = static_cast<int>(checked(j, "views", 0, 1e6));
  c.rotation_error_mean_deg = checked(j, "rotation_error_mean_deg", 0, 360);
  c.rotation_error_max_deg = checked(j, "rotation_error_max_deg", 0, 360);
  c.translation_error_mean_mm = checked(j, "translation_error_mean_mm", 0, 1e12);
  c.translation_error_max_mm = checked(j, "translation_error_max_mm", 0, 1e12);
  c.scan_seconds = checked(j, "scan_seconds", 0, 1e9);
  c.registration_seconds = checked(j, "registration_seconds", 0, 1e9);
  c.segmentation_precision = checked(j, "segmentation_precision", 0, 1);
  c.segmentation_recall = checked(j, "segmentation_recall", 0, 1);
  c.peduncle_kept = checked(j, "peduncle_kept", 0, 1);
  c.body_kept = checked(j, "body_kept", 0, 1);
  c.segmentation_seconds = checked(j, "segmentation_seconds", 0, 1e9);
  c.filter_seconds = checked(j, "filter_seconds", 0, 1e9);
  for (const auto& r : j.at("rows")) {
    EstimateRow e;
    e.estimator = r.at("estimator").get<std::string>();
    e.type = r.at("type").get<std::string>();
    e.quantity = r.at("quantity").get<std::string>();
    e.ok = r.at("ok").get<bool>();
    // A failed row's estimate may be NaN, which JSON writes as null.
    const auto& estimate = r.at("estimate");
    e.estimate = estimate.is_null() ? std::numeric_limits<double>::quiet_NaN() : estimate.get<double>();
    e.truth = r.at("truth").get<double>();
    if (!std::isfinite(e.truth) || (e.ok && !std::isfinite(e.estimate))) throw std::runtime_error("a row's numbers are not finite");
    e.watertight = r.at("watertight").get<bool>();
    e.error = r.at("error").get<std::string>();
    e.seconds = checked(r, "seconds", 0, 1e9);
    e.peak_heap_mb = checked(r, "peak_heap_mb", -1, 1e9);
    e.frame = static_cast<int>(checked(r, "frame", -1, 1e6));
    e.roi = r.at("roi").get<std::string>();
    e.region = static_cast<int>(checked(r, "region", -1, 1e6));
    e.region_points = r.at("region_points").get<std::size_t>();
    e.region_precision = checked(r, "region_precision", -1, 1);
    e.notes = r.at("notes").get<std::string>();
    c.rows.push_back(e);
  }
  if (j.contains("disparity_error_px")) c.disparity_error_px = j.at("disparity_error_px").get<double>();
  if (j.contains("preview_points_mm")) {
    const auto flat = j.at("preview_points_mm").get<std::vector<float>>();
    if (flat.size() % 3 != 0 || flat.size() > 3 * kPreviewPoints) throw std::runtime_error("preview_points_mm: bad size");
    for (std::size_t i = 0; i < flat.size(); i += 3) {
      if (!std::isfinite(flat[i]) || !std::isfinite(flat[i + 1]) || !std::isfinite(flat[i + 2]))
        throw std::runtime_error("preview_points_mm: not finite");
      c.preview_points.push_back({flat[i], flat[i + 1], flat[i + 2]});
    }
  }
  if (j.contains("disparity_outliers")) c.disparity_outliers = j.at("disparity_outliers").get<double>();
  if (j.contains("disparity_fattening")) c.disparity_fattening = checked(j, "disparity_fattening", 0, 1);
  if (j.contains("matched_fraction")) {
    c.matched_fraction = j.at("matched_fraction").get<std::vector<double>>();
    for (const double v : c.matched_fraction)
      if (!(v >= 0 && v <= 1)) throw std::runtime_error("matched_fraction: outside [0, 1]");
  }
  if (j.contains("disparity_locking")) c.disparity_locking = checked(j, "disparity_locking", -1, 1);
  if (j.contains("disparity_bias")) {
    c.disparity_bias = j.at("disparity_bias").get<std::vector<double>>();
    for (const double v : c.disparity_bias)
      if (!(v >= -3 && v <= 3)) throw std::runtime_error("disparity_bias: outside [-3, 3]");
  }
  if (j.contains("disparity_error_correlation")) {
    // NaN (no pairs) is written as null.
    for (const auto& r : j.at("disparity_error_correlation")) {
      const double v = r.is_null() ? std::numeric_limits<double>::quiet_NaN() : r.get<double>();
      if (!(std::isnan(v) || (v >= -1 && v <= 1))) throw std::runtime_error("disparity_error_correlation: outside [-1, 1]");
      c.disparity_error_correlation.push_back(v);
    }
  }
  if (j.contains("pixel_noise_dn")) {
    const auto& v = j.at("pixel_noise_dn");
    if (!v.is_array() || v.size() != 9) throw std::runtime_error("pixel_noise_dn: not 9 values (3 classes x R, G, B)");
    for (const auto& x : v) {
      const double d = x.is_null() ? std::numeric_limits<double>::quiet_NaN() : x.get<double>();
      if (!(std::isnan(d) || (d >= 0 && d <= 255))) throw std::runtime_error("pixel_noise_dn: outside [0, 255]");
      c.pixel_noise_dn.push_back(d);
    }
  }
  if (j.contains("views_registered")) c.views_registered = j.at("views_registered").get<int>();
  if (j.contains("confusion")) {
    for (const auto& m : j.at("confusion")) {
      ConfusionCounts x{m.at("estimator").get<std::string>(), m.at("classes").get<std::vector<std::string>>(),
                        m.at("counts").get<std::vector<long long>>()};
      if (x.counts.size() != x.classes.size() * x.classes.size()) throw std::runtime_error("confusion of the wrong size");
      c.confusion.push_back(std::move(x));
    }
  }
  if (j.contains("detection")) {
    for (const auto& v : j.at("detection")) {
      DetectionView d;
      d.view = v.at("view").get<int>();
      d.station = v.at("station").get<std::string>();
      d.width = v.at("width").get<int>(), d.height = v.at("height").get<int>();
      if (d.width <= 0 || d.height <= 0 || d.width > 65535 || d.height > 65535) throw std::runtime_error("detection: image size");
      auto objects = [&](const nlohmann::json& a) {
        std::vector<CocoObject> out;
        for (const auto& o : a) {
          CocoObject x;
          x.id = static_cast<std::int64_t>(out.size()) + 1;
          x.category_id = o.at("c").get<int>();
          x.score = o.at("s").get<double>();
          x.bbox = o.at("b").get<std::array<double, 4>>();
          x.area = o.at("a").get<double>();
          if (x.category_id < 1 || x.category_id > 5) throw std::runtime_error("detection: category outside 1..5");
          if (!std::isfinite(x.score) || !(x.bbox[2] >= 0) || !(x.bbox[3] >= 0) || !(x.area >= 0) ||
              !std::isfinite(x.bbox[0] + x.bbox[1] + x.bbox[2] + x.bbox[3]))
            throw std::runtime_error("detection: score, box or area out of range");
          x.mask = rle_from_string(o.at("m").get<std::string>(), d.height, d.width);
          out.push_back(std::move(x));
        }
        return out;
      };
      d.truth = objects(v.at("truth"));
      for (const auto& a : v.at("answers"))
        d.answers.emplace_back(a.at("estimator").get<std::string>(), objects(a.at("instances")));
      c.detection.push_back(std::move(d));
    }
  }
  if (j.contains("roc")) {
    for (const auto& r : j.at("roc")) {
      RocSamples s{r.at("estimator").get<std::string>(), r.at("class").get<std::string>(),
                   r.at("tpr").get<std::vector<double>>()};
      if (s.tpr.size() != static_cast<std::size_t>(kRocGrid)) throw std::runtime_error("roc of the wrong length");
      c.roc.push_back(std::move(s));
    }
  }
  return c;
}

}  // namespace grapebench
