#include "bench/case_scores.h"

#include "synth/fnv1a.h"
#include "bench/size_error.h"
#include "synth/rng.h"

#include <algorithm>
#include <map>
#include <cmath>

namespace grapebench {

namespace {

std::string roi_of(const std::string& estimator) {
  const auto at = estimator.find('@');
  return at == std::string::npos ? "" : estimator.substr(at + 1);
}

}  // namespace

std::vector<ComparisonRow> paired_comparisons(const SceneSet& set, const std::vector<ScoreRow>& scores) {
  std::vector<ComparisonRow> out;
  for (std::size_t i = 0; i < scores.size(); ++i) {
    for (std::size_t j = i + 1; j < scores.size(); ++j) {
      const ScoreRow &a = scores[i], &b = scores[j];
      if (a.condition != b.condition || a.quantity != b.quantity || roi_of(a.estimator) != roi_of(b.estimator)) continue;
      std::map<std::string, double> b_error;
      for (std::size_t k = 0; k < b.keys.size(); ++k) b_error[b.keys[k]] = std::abs(b.estimates[k] - b.truths[k]);
      std::vector<double> ea, eb;
      for (std::size_t k = 0; k < a.keys.size(); ++k) {
        const auto it = b_error.find(a.keys[k]);
        if (it == b_error.end()) continue;
        ea.push_back(std::abs(a.estimates[k] - a.truths[k]));
        eb.push_back(it->second);
      }
      const std::uint64_t seed = derive_seed(set.conditions[static_cast<std::size_t>(a.condition)].scene.seed,
                                             fnv1a(a.estimator + "|" + b.estimator + "|" + a.quantity));
      out.push_back({a.condition, a.quantity, a.estimator, b.estimator, compare_paired(ea, eb, seed)});
    }
  }
  return out;
}

std::vector<ScoreRow> score_cases(const SceneSet& set, const std::vector<CaseResult>& cases) {
  std::vector<ScoreRow> out;
  for (std::size_t c = 0; c < set.conditions.size(); ++c) {
    // The scene's estimators, then the rig's floor when the pipeline measures it.
    struct Scored {
      std::string name, type;
      std::vector<Quantity> quantities;
    };
    const Scene& scene = set.conditions[c].scene;
    std::vector<Scored> scored;
    for (const auto& e : scene.estimators) scored.push_back({e.name, e.type, e.quantities});
    if (scene.pipeline.visibility_hull > 0 && scene.protocol == "multi_view") {
      scored.push_back({"visibility_hull", "visibility_hull", {Quantity::Volume}});
    }
    for (const auto& spec : scored) {
      // Single-frame pipelines score each ROI kind apart ("G_E@manual_r").
      std::vector<std::string> rois;
      for (const auto& cr : cases) {
        if (cr.condition != static_cast<int>(c)) continue;
        for (const auto& r : cr.rows) {
          if (r.estimator == spec.name && std::find(rois.begin(), rois.end(), r.roi) == rois.end()) rois.push_back(r.roi);
        }
      }
      if (rois.empty()) rois.push_back("");
      for (const auto& roi : rois) {
        for (const Quantity q : spec.quantities) {
          const std::string qn = quantity_name(q);
          const double k = display_scale(qn);
          std::vector<double> est, truth, secs;
          std::vector<std::string> keys;
          double heap = std::nan("");
          int n = 0;
          for (const auto& cr : cases) {
            if (cr.condition != static_cast<int>(c)) continue;
            for (const auto& r : cr.rows) {
              if (r.estimator != spec.name || r.quantity != qn || r.roi != roi) continue;
              ++n;
              if (cr.ok) secs.push_back(r.seconds);
              if (r.peak_heap_mb >= 0) heap = std::isnan(heap) ? r.peak_heap_mb : std::max(heap, r.peak_heap_mb);
              if (r.ok) {
                est.push_back(r.estimate * k);
                truth.push_back(r.truth * k);
                keys.push_back(std::to_string(cr.bunch) + "/" + std::to_string(r.frame) + "/" + std::to_string(r.region));
              }
            }
          }
          ScoreRow row;
          row.condition = static_cast<int>(c);
          row.estimator = roi.empty() ? spec.name : spec.name + "@" + roi;
          row.type = spec.type;
          row.quantity = qn;
          row.score = score(est, truth, n, secs);
          row.peak_heap_mb_max = heap;
          const std::uint64_t seed = derive_seed(scene.seed, fnv1a(set.conditions[c].label + "|" + row.estimator + "|" + qn));
          row.intervals = bootstrap_score_intervals(est, truth, seed);
          row.concordance = concordance(est, truth);
          row.agreement = bland_altman(est, truth);
          row.keys = std::move(keys);
          row.estimates = std::move(est);
          row.truths = std::move(truth);
          out.push_back(std::move(row));
        }
      }
    }
  }
  return out;
}

std::vector<RegistrationRow> registration_rows(const SceneSet& set, const std::vector<CaseResult>& cases) {
  std::vector<RegistrationRow> rows(set.conditions.size());
  for (const auto& cr : cases) {
    RegistrationRow& r = rows[static_cast<std::size_t>(cr.condition)];
    if (!cr.ok) {
      ++r.failed;
      continue;
    }
    ++r.cases;
    r.rotation_max_deg_mean += cr.rotation_error_max_deg;
    r.translation_max_mm_mean += cr.translation_error_max_mm;
    r.segmentation_precision += cr.segmentation_precision;
    r.segmentation_recall += cr.segmentation_recall;
    r.peduncle_kept += cr.peduncle_kept;
    r.body_kept += cr.body_kept;
    r.rotation_max_deg_worst = std::max(r.rotation_max_deg_worst, cr.rotation_error_max_deg);
  }
  for (auto& r : rows) {
    if (r.cases > 0) {
      r.rotation_max_deg_mean /= r.cases;
      r.translation_max_mm_mean /= r.cases;
      r.segmentation_precision /= r.cases;
      r.segmentation_recall /= r.cases;
      r.peduncle_kept /= r.cases;
      r.body_kept /= r.cases;
    }
  }
  return rows;
}

}  // namespace grapebench
