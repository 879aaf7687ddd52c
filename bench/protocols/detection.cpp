#include "bench/protocols/detection.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "bench/image_truth.h"
#include "bench/instance_mask.h"
#include "bench/protocols/capture.h"
#include "synth/ground_truth.h"

namespace grapebench {

std::vector<CocoObject> answer_objects(const std::vector<ImageDetection>& answers, int width, int height,
                                       const std::vector<std::string>& categories, int& dropped,
                                       std::vector<std::size_t>& source) {
  std::vector<CocoObject> out;
  dropped = 0;
  source.clear();
  for (std::size_t i = 0; i < answers.size(); ++i) {
    const ImageDetection& a = answers[i];
    const std::string where = "instance " + std::to_string(i) + " (" + a.category + ")";
    const auto cat = std::find_if(kDatasetCategories.begin(), kDatasetCategories.end(),
                                  [&](const DatasetCategory& c) { return a.category == c.name; });
    if (cat == kDatasetCategories.end())
      throw InputError(where + ": category must be one of bunch, berry, stalk, leaf, cane");
    if (!std::isfinite(a.score)) throw InputError(where + ": score must be a finite number");
    if (!(std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(a.w) && std::isfinite(a.h)) || a.w < 0 || a.h < 0)
      throw InputError(where + ": box must be finite with width and height >= 0");
    Rle mask = instance_mask(a, width, height, where);  // checked even where dropped
    if (std::find(categories.begin(), categories.end(), a.category) == categories.end()) {
      ++dropped;
      continue;
    }
    CocoObject o;
    o.id = static_cast<std::int64_t>(out.size()) + 1;
    o.category_id = cat->id;
    o.score = a.score;
    o.bbox = {a.x, a.y, a.w, a.h};
    o.mask = std::move(mask);
    o.area = static_cast<double>(rle_area(*o.mask));
    out.push_back(std::move(o));
    source.push_back(i);
  }
  return out;
}

std::vector<EstimateRow> detection_rows(const EstimateRow& base, const std::vector<ImageDetection>& answers,
                                        const std::vector<CocoObject>& answered, const std::vector<std::size_t>& source,
                                        const DetectionView& truth,
                                        const std::vector<int>& truth_bunch, const std::vector<double>& bunch_volumes,
                                        double match_iou) {
  std::vector<EstimateRow> rows;
  EstimateRow n = base;
  n.quantity = "instances";
  n.estimate = static_cast<double>(answered.size());
  n.truth = static_cast<double>(truth.truth.size());
  n.ok = base.error.empty();
  rows.push_back(n);
  // Berry count per visible true bunch: berry answers whose box centre lies on its mask.
  std::vector<std::vector<std::uint8_t>> bunch_mask;
  std::vector<std::size_t> bunches;
  bool berries_scored = false;
  for (std::size_t t = 0; t < truth.truth.size(); ++t) {
    if (truth.truth[t].category_id == kBunch) bunches.push_back(t);
    if (truth.truth[t].category_id == kBerry) berries_scored = true;
  }
  for (const std::size_t t : bunches) {
    EstimateRow b = base;
    b.region = truth_bunch[t];
    if (berries_scored || std::any_of(answered.begin(), answered.end(), [](const CocoObject& o) { return o.category_id == kBerry; })) {
      const std::vector<std::uint8_t> mask = rle_decode(*truth.truth[t].mask);  // row-major
      int found = 0, visible = 0;
      for (const CocoObject& o : answered) {
        if (o.category_id != kBerry) continue;
        const double cu = o.bbox[0] + 0.5 * o.bbox[2], cv = o.bbox[1] + 0.5 * o.bbox[3];
        if (!(cu >= 0 && cv >= 0 && cu < truth.width && cv < truth.height)) continue;  // compared before the cast
        const int u = static_cast<int>(cu), v = static_cast<int>(cv);
        if (mask[static_cast<std::size_t>(v) * truth.width + u])
          ++found;
      }
      for (std::size_t q = 0; q < truth.truth.size(); ++q)
        if (truth.truth[q].category_id == kBerry && truth_bunch[q] == truth_bunch[t]) ++visible;
      b.quantity = "berry_count";
      b.estimate = found, b.truth = visible;
      b.ok = base.error.empty();
      rows.push_back(b);
    }
  }
  // Volumes: answered bunches with one, best score first, each to the unpaired true
  // bunch of highest mask IoU at or above match_iou.
  std::vector<std::size_t> with_volume;
  {
    std::vector<double> volume(answered.size());
    for (std::size_t i = 0; i < answered.size(); ++i) volume[i] = answers[source[i]].volume;
    for (std::size_t i = 0; i < answered.size(); ++i)
      if (answered[i].category_id == kBunch && std::isfinite(volume[i])) with_volume.push_back(i);
    std::stable_sort(with_volume.begin(), with_volume.end(),
                     [&](std::size_t a, std::size_t b) { return answered[a].score > answered[b].score; });
    std::vector<char> taken(truth.truth.size(), 0);
    for (const std::size_t i : with_volume) {
      double best = match_iou;
      std::ptrdiff_t m = -1;
      for (const std::size_t t : bunches) {
        if (taken[t]) continue;
        const double iou = rle_iou(*answered[i].mask, *truth.truth[t].mask);
        if (iou >= best) best = iou, m = static_cast<std::ptrdiff_t>(t);
      }
      if (m < 0) continue;
      taken[static_cast<std::size_t>(m)] = 1;
      EstimateRow v = base;
      v.quantity = "volume";
      v.region = truth_bunch[static_cast<std::size_t>(m)];
      v.estimate = volume[i];
      v.truth = bunch_volumes[static_cast<std::size_t>(v.region)];
      v.ok = true;
      char note[64];
      std::snprintf(note, sizeof note, "mask IoU %.3f", best);
      v.notes = base.notes.empty() ? note : base.notes + "; " + note;
      rows.push_back(v);
    }
  }
  return rows;
}

CaseResult run_detection(const Condition& condition, int condition_index, const BunchJob& job) {
  return guarded_case(condition, condition_index, job, [&](CaseResult& r) {
    const Scene& scene = condition.scene;
    const PipelineSpec& pl = scene.pipeline;
    if (!scene.sensor || !scene.rig) throw InputError(scene.path + ": a run needs `sensor:` and `rig:` sections");
    const auto t0 = std::chrono::steady_clock::now();
    const CaseScene cs = case_scene(scene, job);
    const RayScene rays = scene_rays(scene, cs.scene_bunch, job.seed);
    const LabelScene ls = label_scene(scene, rays);
    std::vector<double> volumes;
    for (const CaseBunch& b : cs.bunches) volumes.push_back(compute_ground_truth(b.original, job.params.density).volume.solid);
    r.scan_seconds = seconds_since(t0);
    r.views = 0;
    // The stream of `grapebench scan` and `grapebench dataset`.
    scan_views(rays, *scene.sensor, *scene.rig, scene.background, scan_seed(job),
               [&](ScanView&& view, std::size_t k) {
      r.scan_seconds += view.seconds;
      ++r.views;
      const auto t_truth = std::chrono::steady_clock::now();
      const ImageTruth truth = image_truth(ls, cs, view.camera, pl.min_pixels, false);
      DetectionView dv;
      dv.view = static_cast<int>(k);
      dv.station = view.rig.name;
      dv.width = truth.width, dv.height = truth.height;
      std::vector<int> truth_bunch;
      for (const ImageInstance& in : truth.instances) {
        const char* name = kDatasetCategories[static_cast<std::size_t>(in.category - 1)].name;
        if (std::find(pl.categories.begin(), pl.categories.end(), name) == pl.categories.end()) continue;
        CocoObject o;
        o.id = static_cast<std::int64_t>(dv.truth.size()) + 1;
        o.category_id = in.category;
        o.mask = in.visible;
        o.area = static_cast<double>(rle_area(in.visible));
        o.bbox = rle_box(in.visible);
        dv.truth.push_back(std::move(o));
        truth_bunch.push_back(in.bunch);
      }
      r.segmentation_seconds += seconds_since(t_truth);  // the labels stand where segmentation does
      EstimatorInput input = image_input(view);
      input.frame->index = static_cast<int>(k);
      for (const EstimatorSpec& spec : scene.estimators) {
        const TimedEstimate t = run_estimator(spec, input);
        EstimateRow base = estimate_row(spec, t);
        base.frame = static_cast<int>(k);
        base.roi = view.rig.name;
        std::vector<EstimateRow> rows;
        if (!t.error.empty()) {
          base.quantity = "instances";
          base.truth = static_cast<double>(dv.truth.size());
          rows.push_back(base);
        } else {
          int dropped = 0;
          std::vector<CocoObject> answered;
          std::vector<std::size_t> source;
          try {
            answered = answer_objects(t.estimate.instances, dv.width, dv.height, pl.categories, dropped, source);
          } catch (const InputError& e) {
            base.quantity = "instances";
            base.ok = false;
            base.error = std::string("answer: ") + e.what();
            base.truth = static_cast<double>(dv.truth.size());
            r.rows.push_back(base);
            continue;
          }
          if (dropped) base.notes += (base.notes.empty() ? "" : "; ") + std::to_string(dropped) + " answers in unscored categories dropped";
          rows = detection_rows(base, t.estimate.instances, answered, source, dv, truth_bunch, volumes, pl.volume_match_iou);
          dv.answers.emplace_back(spec.name, std::move(answered));
        }
        for (EstimateRow& row : rows) r.rows.push_back(std::move(row));
      }
      r.detection.push_back(std::move(dv));
    });
  });
}

}  // namespace grapebench
