#include "bench/case_scores.h"

#include "bench/size_error.h"

#include <algorithm>
#include <cmath>

namespace grapebench {

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
              }
            }
          }
          out.push_back({static_cast<int>(c), roi.empty() ? spec.name : spec.name + "@" + roi, spec.type, qn,
                         score(est, truth, n, secs), heap});
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
