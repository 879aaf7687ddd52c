#include "bench/outputs.h"

#include "bench/build_info.h"
#include "bench/case_scores.h"
#include "bench/classification_tables.h"
#include "bench/detection_tables.h"
#include "bench/protocols/classification.h"
#include "bench/report.h"
#include "bench/scene_file.h"
#include "bench/size_error.h"
#include "bench/stereo_tables.h"
#include "synth/io.h"
#include "synth/utf8.h"

#include <tbb/info.h>


#include <cmath>
#include <map>
#include <cstdio>
#include <fstream>
#include <sstream>

namespace grapebench {

namespace fs = std::filesystem;

namespace {

std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string q = "\"";
  for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

std::string num(double v) {
  if (!std::isfinite(v)) return "NaN";
  char b[32];
  std::snprintf(b, sizeof b, "%.9g", v);
  return b;
}

std::string results_csv(const SceneSet& set, const std::vector<CaseResult>& cases) {
  std::ostringstream s;
  s << "scene,condition";
  for (const auto& a : set.base.sweep) s << "," << csv_field(a.key);
  s << ",bunch,preset,seed,estimator,type,quantity,unit,estimate,truth,error,rel_error_pct,ok,watertight,points,"
       "rotation_error_max_deg,translation_error_max_mm,message,frame,roi,region,region_points,region_precision,notes\n";
  for (const auto& c : cases) {
    const Condition& cond = set.conditions[static_cast<std::size_t>(c.condition)];
    for (const auto& r : c.rows) {
      const double k = display_scale(r.quantity);
      s << csv_field(set.base.name) << "," << csv_field(cond.label);
      for (std::size_t a = 0; a < cond.values.size(); ++a) {
        const auto& names = set.base.sweep[a].names;
        s << "," << (names.empty() ? num(cond.values[a]) : csv_field(names[static_cast<std::size_t>(cond.values[a])]));
      }
      s << "," << c.bunch << "," << c.preset << "," << c.seed << "," << csv_field(r.estimator) << "," << r.type << ","
        << r.quantity << "," << display_unit(r.quantity) << ",";
      if (r.ok) {
        s << num(r.estimate * k) << "," << num(r.truth * k) << "," << num((r.estimate - r.truth) * k) << ","
          << num(100 * (r.estimate / r.truth - 1));
      } else {
        s << "NaN," << (c.ok ? num(r.truth * k) : "NaN") << ",NaN,NaN";
      }
      s << "," << (r.ok ? 1 : 0) << "," << (r.watertight ? 1 : 0) << "," << c.points << ","
        << num(c.rotation_error_max_deg) << "," << num(c.translation_error_max_mm) << "," << csv_field(r.error) << ","
        << r.frame << "," << r.roi << "," << r.region << "," << r.region_points << ","
        << (r.region_precision >= 0 ? num(r.region_precision) : "NaN") << "," << csv_field(r.notes) << "\n";
    }
  }
  return s.str();
}

std::string timings_csv(const SceneSet& set, const std::vector<CaseResult>& cases) {
  std::ostringstream s;
  s << "scene,condition,bunch,estimator,seconds,peak_heap_mb,scan_seconds,segmentation_seconds,registration_seconds,filter_seconds\n";
  for (const auto& c : cases) {
    const Condition& cond = set.conditions[static_cast<std::size_t>(c.condition)];
    std::string last;
    for (const auto& r : c.rows) {
      if (r.estimator == last) continue;  // one timing per estimator run
      last = r.estimator;
      s << csv_field(set.base.name) << "," << csv_field(cond.label) << "," << c.bunch << "," << csv_field(r.estimator)
        << "," << num(r.seconds) << "," << (r.peak_heap_mb >= 0 ? num(r.peak_heap_mb) : "NaN") << ","
        << num(c.scan_seconds) << "," << num(c.segmentation_seconds) << "," << num(c.registration_seconds) << ","
        << num(c.filter_seconds) << "\n";
    }
  }
  return s.str();
}

nlohmann::ordered_json jnum(double v) { return std::isfinite(v) ? nlohmann::ordered_json(v) : nlohmann::ordered_json(); }

std::vector<std::string> condition_labels(const SceneSet& set) {
  std::vector<std::string> labels;
  for (const auto& c : set.conditions) labels.push_back(c.label.empty() ? "all" : c.label);
  return labels;
}

nlohmann::ordered_json interval_json(const Interval& i) { return {jnum(i.lo), jnum(i.hi)}; }

nlohmann::ordered_json summary_json(const SceneSet& set, const std::vector<CaseResult>& cases,
                                    const std::vector<ScoreRow>& scores) {
  nlohmann::ordered_json j;
  j["scene"] = set.base.name;
  j["cases"] = cases.size();
  int failed = 0;
  for (const auto& c : cases) failed += c.ok ? 0 : 1;
  j["failed_scans"] = failed;
  nlohmann::ordered_json conds = nlohmann::ordered_json::array();
  for (const auto& c : set.conditions) conds.push_back(c.label);
  j["conditions"] = conds;
  // Seed 004: each classification row's mean over the cases, with its range.
  nlohmann::ordered_json classes = nlohmann::ordered_json::array();
  for (const ClassificationCell& c : classification_cells(cases, condition_labels(set))) {
    classes.push_back({{"condition", c.condition}, {"estimator", c.estimator}, {"quantity", c.quantity},
                       {"cases", c.cases}, {"mean", jnum(c.mean)}, {"min", jnum(c.min)}, {"max", jnum(c.max)}});
  }
  if (!classes.empty()) {
    j["classification"] = classes;
    const std::vector<std::string> labels = condition_labels(set);
    nlohmann::ordered_json rec = nlohmann::ordered_json::array();
    for (const auto& c : cases) {
      if (c.disparity_error_px >= 0)
        rec.push_back({{"condition", labels[static_cast<std::size_t>(c.condition)]}, {"bunch", c.bunch},
                       {"points", c.points}, {"disparity_error_px", jnum(c.disparity_error_px)},
                       {"disparity_outliers", jnum(c.disparity_outliers)}});
      if (c.disparity_error_px >= 0 && !c.disparity_error_correlation.empty()) {
        nlohmann::ordered_json r = nlohmann::ordered_json::array();
        for (const double v : c.disparity_error_correlation) r.push_back(jnum(v));
        rec.back()["disparity_error_correlation_1_2_4_8px"] = r;
        rec.back()["disparity_fattening"] = jnum(c.disparity_fattening);
        nlohmann::ordered_json m = nlohmann::ordered_json::object();
        for (std::size_t k = 0; k < c.matched_fraction.size() && k < plant_classes().size(); ++k)
          m[plant_classes()[k]] = jnum(c.matched_fraction[k]);
        rec.back()["matched_fraction"] = m;
        rec.back()["disparity_locking"] = jnum(c.disparity_locking);
        nlohmann::ordered_json bias = nlohmann::ordered_json::object();
        for (std::size_t k = 0; k < c.disparity_bias.size() && k < plant_classes().size(); ++k)
          bias[plant_classes()[k]] = jnum(c.disparity_bias[k]);
        rec.back()["disparity_bias"] = bias;
        if (c.pixel_noise_dn.size() == 3 * plant_classes().size()) {
          nlohmann::ordered_json noise = nlohmann::ordered_json::object();
          for (std::size_t k = 0; k < plant_classes().size(); ++k)
            noise[plant_classes()[k]] = {jnum(c.pixel_noise_dn[3 * k]), jnum(c.pixel_noise_dn[3 * k + 1]),
                                         jnum(c.pixel_noise_dn[3 * k + 2])};
          rec.back()["pixel_noise_dn"] = noise;
        }
      }
    }
    j["reconstruction"] = rec;
    nlohmann::ordered_json conf = nlohmann::ordered_json::array();
    for (std::size_t k = 0; k < set.conditions.size(); ++k) {
      for (const PooledConfusion& p : pooled_confusion(cases, static_cast<int>(k))) {
        conf.push_back({{"condition", labels[k]}, {"estimator", p.estimator}, {"classes", p.classes},
                        {"counts", p.counts}, {"pooled_accuracy", jnum(p.accuracy)}, {"pooled_miou", jnum(p.miou)}});
      }
    }
    j["confusion"] = conf;
  }
  // Seed 001: Table 2's success rates and Table 1 / Fig. 11's depth cells, so
  // `grapebench check` can gate the stereo_pair protocol.
  const StereoTables st = stereo_tables(cases, condition_labels(set));
  if (!st.empty()) {
    nlohmann::ordered_json succ = nlohmann::ordered_json::array(), depth = nlohmann::ordered_json::array();
    for (const SuccessCell& c : st.success) {
      succ.push_back({{"condition", c.condition}, {"estimator", c.estimator}, {"pairs", c.pairs},
                      {"successes", c.successes}, {"rate", jnum(c.rate)}, {"ci95", {jnum(c.lo), jnum(c.hi)}}});
    }
    for (const DepthCell& c : st.depth) {
      depth.push_back({{"estimator", c.estimator}, {"depth_mm", c.depth_mm}, {"pairs", c.pairs},
                       {"visible", c.visible}, {"found", c.found},
                       {"found_rate", jnum(c.visible ? static_cast<double>(c.found) / c.visible : NAN)},
                       {"answered", c.answered}, {"ez_mm", jnum(c.answered ? c.ez_mm : NAN)},
                       {"ex_mm", jnum(c.answered ? c.ex_mm : NAN)}});
    }
    j["stereo"] = {{"cut_success", succ}, {"depth", depth}};
  }
  // Detection: COCO's numbers per condition, station and estimator, with intervals.
  std::vector<int> max_detections;
  for (const auto& c : set.conditions) max_detections.push_back(c.scene.pipeline.max_detections);
  const DetectionTables dt = detection_tables(cases, condition_labels(set), max_detections, set.base.seed);
  if (!dt.empty()) {
    // COCO's names, AR_100 named after the limit in force (AR_<max_detections>).
    int limit = 100;
    auto stats = [&](const std::array<double, 12>& v) {
      nlohmann::ordered_json o;
      for (std::size_t k = 0; k < v.size(); ++k) o[coco_stat_name(k, {1, 10, limit})] = jnum(v[k]);
      return o;
    };
    nlohmann::ordered_json cells = nlohmann::ordered_json::array(), pairs = nlohmann::ordered_json::array();
    for (const DetectionCell& c : dt.cells) {
      limit = c.max_detections;
      nlohmann::ordered_json cats = nlohmann::ordered_json::array();
      for (std::size_t k = 0; k < c.result.per_category.size(); ++k)
        cats.push_back({{"category", c.result.per_category[k].first.name},
                        {"stats", stats(c.result.per_category[k].second)},
                        {"AP_ci95", interval_json(c.intervals.per_category[k].first)},
                        {"AP50_ci95", interval_json(c.intervals.per_category[k].second)}});
      cells.push_back({{"condition", c.condition}, {"station", c.station}, {"estimator", c.estimator},
                       {"iou_type", c.iou_type}, {"images", c.images}, {"max_detections", c.max_detections},
                       {"stats", stats(c.result.stats)},
                       {"AP_ci95", interval_json(c.intervals.ap)}, {"AP50_ci95", interval_json(c.intervals.ap50)},
                       {"per_category", cats}});
    }
    for (const DetectionComparison& d : dt.comparisons) {
      nlohmann::ordered_json cats = nlohmann::ordered_json::array();
      for (const auto& [ap, ap50] : d.difference.per_category)
        cats.push_back({{"AP_difference_ci95", interval_json(ap)}, {"AP50_difference_ci95", interval_json(ap50)}});
      pairs.push_back({{"condition", d.condition}, {"station", d.station}, {"a", d.a}, {"b", d.b},
                       {"iou_type", d.iou_type}, {"images", d.images}, {"AP_difference", jnum(d.ap_difference)},
                       {"AP_difference_ci95", interval_json(d.difference.ap)},
                       {"AP50_difference", jnum(d.ap50_difference)},
                       {"AP50_difference_ci95", interval_json(d.difference.ap50)}, {"per_category", cats}});
    }
    j["detection"] = {{"cells", cells}, {"paired_comparisons", pairs}};
  }
  nlohmann::ordered_json rows = nlohmann::ordered_json::array();
  for (const auto& r : scores) {
    const Score& s = r.score;
    rows.push_back({{"condition", set.conditions[static_cast<std::size_t>(r.condition)].label},
                    {"estimator", r.estimator},
                    {"type", r.type},
                    {"quantity", r.quantity},
                    {"unit", display_unit(r.quantity)},
                    {"cases", s.cases},
                    {"succeeded", s.succeeded},
                    {"success_rate", jnum(s.success_rate)},
                    {"r2", jnum(s.r2)},
                    {"r2_identity", jnum(s.r2_identity)},
                    {"rmse", jnum(s.rmse)},
                    {"mae", jnum(s.mae)},
                    {"bias", jnum(s.bias)},
                    {"mape_pct", jnum(s.mape)},
                    {"slope", jnum(s.slope)},
                    {"intercept", jnum(s.intercept)},
                    {"rmse_ci95", interval_json(r.intervals.rmse)},
                    {"bias_ci95", interval_json(r.intervals.bias)},
                    {"mape_pct_ci95", interval_json(r.intervals.mape)},
                    {"r2_ci95", interval_json(r.intervals.r2)},
                    {"concordance", jnum(r.concordance)},
                    {"limits_of_agreement", {jnum(r.agreement.lower), jnum(r.agreement.upper)}}});
  }
  j["scores"] = rows;
  // Paired comparisons: d = |error of a| - |error of b| per measurement both made
  // (negative: a is closer to the truth), display units.
  nlohmann::ordered_json pairs = nlohmann::ordered_json::array();
  for (const ComparisonRow& c : paired_comparisons(set, scores)) {
    const PairedComparison& p = c.comparison;
    pairs.push_back({{"condition", set.conditions[static_cast<std::size_t>(c.condition)].label},
                     {"quantity", c.quantity},
                     {"unit", display_unit(c.quantity)},
                     {"a", c.a},
                     {"b", c.b},
                     {"cases", p.cases},
                     {"mean_abs_error_difference", jnum(p.mean_difference)},
                     {"ci95", interval_json(p.interval)},
                     {"wilcoxon_p", jnum(p.test.p)},
                     {"wilcoxon_w_plus", jnum(p.test.w_plus)},
                     {"wilcoxon_nonzero", p.test.n}});
  }
  j["paired_comparisons"] = pairs;
  nlohmann::ordered_json reg = nlohmann::ordered_json::array();
  const auto regs = registration_rows(set, cases);
  for (std::size_t c = 0; c < set.conditions.size(); ++c) {
    reg.push_back({{"condition", set.conditions[c].label},
                   {"registration", registration_label(set.conditions[c].scene)},
                   {"rotation_error_max_deg_mean", regs[c].rotation_max_deg_mean},
                   {"rotation_error_max_deg_worst", regs[c].rotation_max_deg_worst},
                   {"translation_error_max_mm_mean", regs[c].translation_max_mm_mean},
                   {"segmentation", set.conditions[c].scene.pipeline.segmentation_name()},
                   {"segmentation_precision_mean", regs[c].segmentation_precision},
                   {"segmentation_recall_mean", regs[c].segmentation_recall},
                   {"peduncle_kept_mean", regs[c].peduncle_kept},
                   {"body_kept_mean", regs[c].body_kept},
                   {"protocol", set.conditions[c].scene.protocol}});
  }
  j["registration"] = reg;
  return j;
}

nlohmann::ordered_json timings_json(const SceneSet& set, const std::vector<ScoreRow>& scores) {
  nlohmann::ordered_json rows = nlohmann::ordered_json::array();
  std::string last;
  for (const auto& r : scores) {
    const std::string id = std::to_string(r.condition) + "/" + r.estimator;
    if (id == last) continue;
    last = id;
    rows.push_back({{"condition", set.conditions[static_cast<std::size_t>(r.condition)].label},
                    {"estimator", r.estimator},
                    {"median_s", jnum(r.score.time_median)},
                    {"p25_s", jnum(r.score.time_p25)},
                    {"p75_s", jnum(r.score.time_p75)},
                    {"peak_heap_mb_max", jnum(r.peak_heap_mb_max)}});
  }
  return rows;
}


std::string leaderboard(const SceneSet& set, const std::vector<CaseResult>& cases, const std::vector<ScoreRow>& scores) {
  std::ostringstream s;
  char line[256];
  for (std::size_t c = 0; c < set.conditions.size(); ++c) {
    if (!set.conditions[c].label.empty()) s << "-- " << set.conditions[c].label << "\n";
    std::snprintf(line, sizeof line, "  %-18s %-8s %5s %8s %10s %10s %9s %15s %8s %10s %8s\n", "estimator", "quantity",
                  "ok", "R2", "RMSE", "bias", "MAPE %", "MAPE 95% CI", "slope", "time ms", "heap MB");
    s << line;
    // Volume first, best MAPE first: the leaderboard.
    std::vector<const ScoreRow*> rows;
    for (const auto& r : scores) {
      if (r.condition == static_cast<int>(c)) rows.push_back(&r);
    }
    std::stable_sort(rows.begin(), rows.end(), [](const ScoreRow* a, const ScoreRow* b) {
      if (a->quantity != b->quantity) return a->quantity == "volume" || (b->quantity != "volume" && a->quantity < b->quantity);
      const double ma = std::isfinite(a->score.mape) ? a->score.mape : 1e300;
      const double mb = std::isfinite(b->score.mape) ? b->score.mape : 1e300;
      return ma < mb;
    });
    for (const ScoreRow* r : rows) {
      const Score& x = r->score;
      char ok[16];
      std::snprintf(ok, sizeof ok, "%d/%d", x.succeeded, x.cases);
      char ci[32];
      std::snprintf(ci, sizeof ci, "[%.1f, %.1f]", r->intervals.mape.lo, r->intervals.mape.hi);
      std::snprintf(line, sizeof line, "  %-18s %-8s %5s %8.3f %10.2f %10.2f %9.1f %15s %8.3f %10.2f %8.1f  %s\n",
                    r->estimator.c_str(), r->quantity.c_str(), ok, x.r2, x.rmse, x.bias, x.mape, ci, x.slope,
                    x.time_median * 1e3, r->peak_heap_mb_max, display_unit(r->quantity));
      s << line;
    }
  }
  const std::vector<ClassificationCell> cells = classification_cells(cases, condition_labels(set));
  if (!cells.empty()) {
    std::snprintf(line, sizeof line, "  %-18s %-16s %-18s %5s %8s %8s %8s\n", "condition", "estimator", "quantity",
                  "cases", "mean", "min", "max");
    s << "classification (test part of each row section):\n" << line;
    for (const ClassificationCell& c : cells) {
      std::snprintf(line, sizeof line, "  %-18s %-16s %-18s %5d %8.4f %8.4f %8.4f\n", c.condition.c_str(),
                    c.estimator.c_str(), c.quantity.c_str(), c.cases, c.mean, c.min, c.max);
      s << line;
    }
  }
  return s.str();
}

}  // namespace

nlohmann::ordered_json manifest_json(const SceneSet& set, const std::vector<CaseResult>& cases, int threads) {
  nlohmann::ordered_json j;
  j["scene_file"] = set.base.path;
  std::string text;
  try {
    text = read_scene_text(set.base.path);
  } catch (const InputError& e) {
    text = std::string("(unreadable at the end of the run: ") + e.what() + ")";
  }
  j["scene_text"] = escape_invalid_utf8(text);  // the file may have changed since it was read
  nlohmann::ordered_json sweep = nlohmann::ordered_json::array();
  for (const auto& a : set.base.sweep) sweep.push_back({{"key", a.key}, {"values", a.values}});
  j["sweep"] = sweep;
  nlohmann::ordered_json conds = nlohmann::ordered_json::array();
  for (const auto& c : set.conditions) {
    nlohmann::ordered_json cj = {{"condition", c.label}, {"scene", scene_json(c.scene)}};
    nlohmann::ordered_json seeds = nlohmann::ordered_json::array();
    for (const auto& job : bunch_jobs(c.scene)) seeds.push_back({{"bunch", job.index}, {"preset", job.preset}, {"seed", job.seed}});
    cj["bunch_seeds"] = seeds;
    conds.push_back(cj);
  }
  j["conditions"] = conds;
  j["build"] = build_info_json();
  // Which builds computed the cases (more than one only with --reuse-other-builds).
  std::map<std::string, int> builds;
  for (const auto& c : cases) ++builds[c.build];
  j["case_builds"] = builds;
  j["machine"] = machine_json();
  j["threads"] = threads;
  return j;
}

std::string write_outputs(const SceneSet& set, const std::vector<CaseResult>& cases, const std::filesystem::path& out,
                          int threads) {
  const auto scores = score_cases(set, cases);
  write_file_atomic(out / "results.csv", results_csv(set, cases));
  write_file_atomic(out / "timings.csv", timings_csv(set, cases));
  write_file_atomic(out / "summary.json", summary_json(set, cases, scores).dump(1) + "\n");
  write_file_atomic(out / "timings.json", timings_json(set, scores).dump(1) + "\n");
  write_file_atomic(out / "manifest.json", manifest_json(set, cases, threads).dump(1) + "\n");
  const auto size_cells = size_error_cells(set, cases);
  if (!size_cells.empty()) {
    write_file_atomic(out / "size_error.csv", size_error_csv(set, size_cells));
    write_file_atomic(out / "size_error_table.md", size_error_table(size_cells));
  }
  const Report report = make_report(set, cases, scores, size_cells);
  fs::create_directories(out / "plots");
  for (const auto& [name, svg] : report.svgs) write_file_atomic(out / "plots" / name, svg);
  write_file_atomic(out / "report.html", report.html);
  return leaderboard(set, cases, scores);
}

}  // namespace grapebench
