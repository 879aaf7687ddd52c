#include "bench/detection_tables.h"

#include <map>
#include <set>

#include "synth/fnv1a.h"
#include "bench/image_truth.h"
#include "synth/rng.h"

namespace grapebench {

DetectionTables detection_tables(const std::vector<CaseResult>& cases, const std::vector<std::string>& labels,
                                 const std::vector<int>& max_detections, std::uint64_t seed, int resamples) {
  DetectionTables out;
  for (std::size_t c = 0; c < labels.size(); ++c) {
    // The views of the condition, in case order, and their stations and estimators.
    std::vector<const DetectionView*> views;
    std::vector<std::size_t> view_case;  // the case each view comes from (its resampling unit)
    std::vector<std::string> stations, estimators;
    std::set<int> categories;
    for (const CaseResult& cr : cases) {
      if (cr.condition != static_cast<int>(c)) continue;
      for (const DetectionView& v : cr.detection) {
        views.push_back(&v);
        view_case.push_back(static_cast<std::size_t>(&cr - cases.data()));
        if (std::find(stations.begin(), stations.end(), v.station) == stations.end()) stations.push_back(v.station);
        for (const auto& [name, list] : v.answers)
          if (std::find(estimators.begin(), estimators.end(), name) == estimators.end()) estimators.push_back(name);
        for (const CocoObject& o : v.truth) categories.insert(o.category_id);
      }
    }
    if (views.empty()) continue;
    std::vector<std::string> groups{"all"};
    if (stations.size() > 1) groups.insert(groups.end(), stations.begin(), stations.end());
    for (const std::string& group : groups) {
      CocoGroundTruth gt;
      for (const int k : categories) gt.categories.push_back({k, kDatasetCategories[static_cast<std::size_t>(k - 1)].name});
      std::vector<const DetectionView*> in;
      std::map<std::size_t, std::vector<std::size_t>> by_case;  // the case's image positions
      for (std::size_t k = 0; k < views.size(); ++k)
        if (group == "all" || views[k]->station == group) {
          by_case[view_case[k]].push_back(in.size());
          in.push_back(views[k]);
        }
      std::vector<std::vector<std::size_t>> units;
      for (auto& [c_index, positions] : by_case) units.push_back(std::move(positions));
      std::int64_t next_id = 1;
      for (std::size_t i = 0; i < in.size(); ++i) {
        const std::int64_t image = static_cast<std::int64_t>(i) + 1;
        gt.images.push_back({image, in[i]->width, in[i]->height});
        for (CocoObject o : in[i]->truth) {
          o.image_id = image, o.id = next_id++;
          gt.annotations.push_back(std::move(o));
        }
      }
      for (const char* type : {"segm", "bbox"}) {
        CocoEvalParams params;
        params.type = std::string(type) == "segm" ? CocoIouType::Segm : CocoIouType::Bbox;
        params.max_dets = {1, 10, max_detections[c]};
        std::vector<CocoEvaluation> evals;
        for (const std::string& name : estimators) {
          std::vector<CocoObject> dets;
          for (std::size_t i = 0; i < in.size(); ++i)
            for (const auto& [who, list] : in[i]->answers) {
              if (who != name) continue;
              for (CocoObject o : list) {
                o.image_id = static_cast<std::int64_t>(i) + 1;
                // COCO's loadRes: a box result's area is w x h (the area ranges' test).
                if (params.type == CocoIouType::Bbox) o.area = o.bbox[2] * o.bbox[3];
                o.id = static_cast<std::int64_t>(dets.size()) + 1;
                dets.push_back(std::move(o));
              }
            }
          evals.push_back(coco_evaluate_images(gt, dets, params));
          DetectionCell cell;
          cell.condition = labels[c], cell.station = group, cell.estimator = name, cell.iou_type = type;
          cell.images = static_cast<int>(in.size());
          cell.max_detections = max_detections[c];
          std::vector<std::size_t> all(in.size());
          for (std::size_t i = 0; i < all.size(); ++i) all[i] = i;
          cell.result = coco_accumulate(evals.back(), all, true);
          cell.intervals =
              coco_bootstrap(evals.back(), derive_seed(seed, fnv1a(labels[c] + "|" + group + "|" + type)), resamples, 0.95, units);
          out.cells.push_back(std::move(cell));
        }
        // Paired: every two estimators over the same resamples of the images.
        for (std::size_t a = 0; a < estimators.size(); ++a)
          for (std::size_t b = a + 1; b < estimators.size(); ++b) {
            DetectionComparison d;
            d.condition = labels[c], d.station = group, d.a = estimators[a], d.b = estimators[b], d.iou_type = type;
            d.images = static_cast<int>(in.size());
            const CocoEvalResult& ra = out.cells[out.cells.size() - estimators.size() + a].result;
            const CocoEvalResult& rb = out.cells[out.cells.size() - estimators.size() + b].result;
            d.ap_difference = ra.stats[0] - rb.stats[0];
            d.ap50_difference = ra.stats[1] - rb.stats[1];
            d.difference = coco_bootstrap_difference(evals[a], evals[b],
                                                     derive_seed(seed, fnv1a(labels[c] + "|" + group + "|" + type)),
                                                     resamples, 0.95, units);
            out.comparisons.push_back(std::move(d));
          }
      }
    }
  }
  return out;
}

}  // namespace grapebench
