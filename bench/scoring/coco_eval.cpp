#include "bench/scoring/coco_eval.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <set>
#include <stdexcept>
#include <unordered_map>

#include "synth/config.h"

namespace grapebench {

namespace {

using Json = nlohmann::json;

[[noreturn]] void fail(const std::string& file, const std::string& where, const std::string& what) {
  throw InputError(file + ": " + where + ": " + what);
}

std::string record(const char* list, std::size_t i) { return std::string(list) + "[" + std::to_string(i) + "]"; }

std::int64_t get_id(const Json& r, const char* key, const std::string& file, const std::string& where) {
  if (!r.contains(key)) fail(file, where, std::string("missing `") + key + "`");
  const Json& v = r[key];
  if (!v.is_number_integer()) fail(file, where, std::string("`") + key + "` must be an integer");
  return v.get<std::int64_t>();
}

double get_number(const Json& r, const char* key, const std::string& file, const std::string& where) {
  if (!r.contains(key) || !r[key].is_number()) fail(file, where, std::string("`") + key + "` must be a number");
  const double x = r[key].get<double>();
  if (!std::isfinite(x)) fail(file, where, std::string("`") + key + "` is not finite");
  return x;
}

std::array<double, 4> get_box(const Json& r, const std::string& file, const std::string& where) {
  const Json& b = r["bbox"];
  if (!b.is_array() || b.size() != 4) fail(file, where, "`bbox` must be [x, y, w, h]");
  std::array<double, 4> out{};
  for (std::size_t k = 0; k < 4; ++k) {
    if (!b[k].is_number()) fail(file, where, "`bbox` must hold 4 numbers");
    out[k] = b[k].get<double>();
    if (!std::isfinite(out[k])) fail(file, where, "`bbox` holds a NaN or infinite value");
  }
  if (out[2] < 0 || out[3] < 0) fail(file, where, "`bbox` has a negative width or height (allowed: w, h >= 0)");
  return out;
}

Rle get_mask(const Json& r, const std::string& file, const std::string& where, const CocoImage& im) {
  const Json& s = r["segmentation"];
  if (!s.is_object())
    fail(file, where, "`segmentation` must be RLE {size: [h, w], counts: string} (polygons are not read)");
  const Json& size = s["size"];
  if (!size.is_array() || size.size() != 2 || !size[0].is_number_integer() || !size[1].is_number_integer())
    fail(file, where, "`segmentation.size` must be [h, w]");
  const int h = size[0].get<int>(), w = size[1].get<int>();
  if (h != im.height || w != im.width)
    fail(file, where, "mask of " + std::to_string(h) + " x " + std::to_string(w) + " (h x w) on image " +
                          std::to_string(im.id) + " of " + std::to_string(im.height) + " x " + std::to_string(im.width));
  if (!s["counts"].is_string()) fail(file, where, "`segmentation.counts` must be a compressed RLE string");
  try {
    return rle_from_string(s["counts"].get<std::string>(), h, w);
  } catch (const std::invalid_argument& e) {
    fail(file, where, std::string("`segmentation.counts`: ") + e.what());
  }
}

}  // namespace

CocoGroundTruth read_coco_ground_truth(const Json& j, const std::string& file) {
  if (!j.is_object()) fail(file, "top level", "a COCO object {images, categories, annotations}");
  CocoGroundTruth gt;
  std::set<std::int64_t> image_ids, ann_ids;
  std::set<int> cat_ids;
  for (const char* key : {"images", "categories", "annotations"})
    if (!j.contains(key) || !j[key].is_array()) fail(file, key, "missing or not a list");
  for (std::size_t i = 0; i < j["images"].size(); ++i) {
    const Json& r = j["images"][i];
    const std::string where = record("images", i);
    CocoImage im{get_id(r, "id", file, where), static_cast<int>(get_id(r, "width", file, where)),
                 static_cast<int>(get_id(r, "height", file, where))};
    if (im.width <= 0 || im.height <= 0 || im.width > 65535 || im.height > 65535)
      fail(file, where, "width and height must be in [1, 65535]");
    if (!image_ids.insert(im.id).second) fail(file, where, "duplicate image id " + std::to_string(im.id));
    gt.images.push_back(im);
  }
  for (std::size_t i = 0; i < j["categories"].size(); ++i) {
    const Json& r = j["categories"][i];
    const std::string where = record("categories", i);
    CocoCategory c{static_cast<int>(get_id(r, "id", file, where)), r.value("name", std::string())};
    if (!cat_ids.insert(c.id).second) fail(file, where, "duplicate category id " + std::to_string(c.id));
    gt.categories.push_back(c);
  }
  std::unordered_map<std::int64_t, std::size_t> image_at;
  for (std::size_t i = 0; i < gt.images.size(); ++i) image_at[gt.images[i].id] = i;
  for (std::size_t i = 0; i < j["annotations"].size(); ++i) {
    const Json& r = j["annotations"][i];
    const std::string where = record("annotations", i);
    CocoObject a;
    a.id = get_id(r, "id", file, where);
    if (a.id <= 0) fail(file, where, "ids start at 1 (COCOeval reads id 0 as unmatched)");
    if (!ann_ids.insert(a.id).second) fail(file, where, "duplicate annotation id " + std::to_string(a.id));
    a.image_id = get_id(r, "image_id", file, where);
    const auto it = image_at.find(a.image_id);
    if (it == image_at.end()) fail(file, where, "image_id " + std::to_string(a.image_id) + " is not in `images`");
    a.category_id = static_cast<int>(get_id(r, "category_id", file, where));
    if (!cat_ids.count(a.category_id))
      fail(file, where, "category_id " + std::to_string(a.category_id) + " is not in `categories`");
    a.bbox = get_box(r, file, where);
    a.area = get_number(r, "area", file, where);
    if (a.area < 0) fail(file, where, "`area` is negative");
    a.iscrowd = r.value("iscrowd", 0) != 0;
    if (r.contains("segmentation") && r["segmentation"].is_object())
      a.mask = get_mask(r, file, where, gt.images[it->second]);
    gt.annotations.push_back(std::move(a));
  }
  return gt;
}

std::vector<CocoObject> read_coco_results(const Json& j, const std::string& file, const CocoGroundTruth& gt,
                                          CocoIouType type) {
  if (!j.is_array()) fail(file, "top level", "COCO results are a list of {image_id, category_id, score, bbox or segmentation}");
  std::unordered_map<std::int64_t, const CocoImage*> images;
  for (const CocoImage& im : gt.images) images[im.id] = &im;
  std::set<int> cats;
  for (const CocoCategory& c : gt.categories) cats.insert(c.id);
  std::set<std::int64_t> ids;
  std::vector<CocoObject> out;
  for (std::size_t i = 0; i < j.size(); ++i) {
    const Json& r = j[i];
    const std::string where = "record " + std::to_string(i);
    if (!r.is_object()) fail(file, where, "not an object");
    CocoObject d;
    d.image_id = get_id(r, "image_id", file, where);
    const auto it = images.find(d.image_id);
    if (it == images.end()) fail(file, where, "image_id " + std::to_string(d.image_id) + " is not an image of the ground truth");
    d.category_id = static_cast<int>(get_id(r, "category_id", file, where));
    if (!cats.count(d.category_id))
      fail(file, where, "category_id " + std::to_string(d.category_id) + " is not a category of the ground truth");
    d.score = get_number(r, "score", file, where);
    if (r.contains("id")) {
      d.id = get_id(r, "id", file, where);
      if (!ids.insert(d.id).second) fail(file, where, "duplicate id " + std::to_string(d.id));
    }
    if (type == CocoIouType::Segm) {
      if (!r.contains("segmentation")) fail(file, where, "missing `segmentation` (scoring masks)");
      d.mask = get_mask(r, file, where, *it->second);
      d.area = static_cast<double>(rle_area(*d.mask));
      d.bbox = r.contains("bbox") ? get_box(r, file, where) : rle_box(*d.mask);
    } else {
      if (!r.contains("bbox")) fail(file, where, "missing `bbox` (scoring boxes)");
      d.bbox = get_box(r, file, where);
      d.area = d.bbox[2] * d.bbox[3];
    }
    out.push_back(std::move(d));
  }
  // Numbered as COCO's loadRes does, whatever ids they carry: 1, 2, ... in file order.
  for (std::size_t i = 0; i < out.size(); ++i) out[i].id = static_cast<std::int64_t>(i) + 1;
  return out;
}

namespace {

double box_iou(const std::array<double, 4>& d, const std::array<double, 4>& g, bool crowd) {
  const double w = std::min(d[0] + d[2], g[0] + g[2]) - std::max(d[0], g[0]);
  const double h = std::min(d[1] + d[3], g[1] + g[3]) - std::max(d[1], g[1]);
  if (w <= 0 || h <= 0) return 0;
  const double inter = w * h, da = d[2] * d[3], ga = g[2] * g[3];
  const double uni = crowd ? da : da + ga - inter;
  return uni > 0 ? inter / uni : 0;
}

struct ImageEval {  // one image and category at one area range
  std::vector<double> scores;               // detections, best first, at most max_dets.back()
  std::vector<std::vector<char>> matched;   // [threshold][detection]
  std::vector<std::vector<char>> ignored;   // [threshold][detection]
  std::vector<char> gt_ignored;             // [ground truth]
};

}  // namespace

CocoEvalResult coco_evaluate(const CocoGroundTruth& gt, const std::vector<CocoObject>& dets, const CocoEvalParams& p) {
  if (p.max_dets.size() != 3) throw std::invalid_argument("coco_evaluate: three max_dets");
  // np.linspace's values, so thresholds compare as COCOeval's do.
  std::vector<double> iou_thr(10), rec_thr(101);
  for (int i = 0; i < 10; ++i) iou_thr[static_cast<std::size_t>(i)] = i * ((0.95 - 0.5) / 9) + 0.5;
  iou_thr[9] = 0.95;
  for (int i = 0; i < 101; ++i) rec_thr[static_cast<std::size_t>(i)] = i * (1.0 / 100) + 0.0;
  rec_thr[100] = 1.0;
  const std::array<std::array<double, 2>, 4> areas{{{0, 1e10}, {0, 32.0 * 32}, {32.0 * 32, 96.0 * 96}, {96.0 * 96, 1e10}}};
  const std::size_t T = iou_thr.size(), R = rec_thr.size(), A = areas.size(), M = p.max_dets.size();
  const int max_det = p.max_dets.back();

  // Images in id order, categories in id order (COCOeval's sorted imgIds and catIds).
  std::vector<std::int64_t> image_ids;
  for (const CocoImage& im : gt.images) image_ids.push_back(im.id);
  std::sort(image_ids.begin(), image_ids.end());
  std::vector<CocoCategory> cats = gt.categories;
  std::sort(cats.begin(), cats.end(), [](const CocoCategory& a, const CocoCategory& b) { return a.id < b.id; });
  const std::size_t K = cats.size();
  std::map<std::pair<std::int64_t, int>, std::vector<const CocoObject*>> gts, dts;
  for (const CocoObject& g : gt.annotations) gts[{g.image_id, g.category_id}].push_back(&g);
  for (const CocoObject& d : dets) dts[{d.image_id, d.category_id}].push_back(&d);

  // precision[t][r][k][a][m], recall[t][k][a][m]: -1 where undefined.
  auto pidx = [&](std::size_t t, std::size_t r, std::size_t k, std::size_t a, std::size_t m) {
    return (((t * R + r) * K + k) * A + a) * M + m;
  };
  auto ridx = [&](std::size_t t, std::size_t k, std::size_t a, std::size_t m) { return ((t * K + k) * A + a) * M + m; };
  std::vector<double> precision(T * R * K * A * M, -1.0), recall(T * K * A * M, -1.0);

  for (std::size_t k = 0; k < K; ++k) {
    // The IoUs of each image once: detections best first (stable), cut at max_det.
    struct PerImage {
      std::vector<const CocoObject*> g, d;
      std::vector<std::vector<double>> iou;  // [detection][ground truth]
    };
    std::vector<PerImage> per;
    for (const std::int64_t img : image_ids) {
      PerImage e;
      const auto gi = gts.find({img, cats[k].id});
      const auto di = dts.find({img, cats[k].id});
      if (gi != gts.end()) e.g = gi->second;
      if (di != dts.end()) e.d = di->second;
      if (e.g.empty() && e.d.empty()) continue;
      std::stable_sort(e.d.begin(), e.d.end(), [](const CocoObject* a, const CocoObject* b) { return a->score > b->score; });
      if (e.d.size() > static_cast<std::size_t>(max_det)) e.d.resize(static_cast<std::size_t>(max_det));
      e.iou.assign(e.d.size(), std::vector<double>(e.g.size(), 0.0));
      for (std::size_t a = 0; a < e.d.size(); ++a)
        for (std::size_t b = 0; b < e.g.size(); ++b) {
          if (p.type == CocoIouType::Bbox) {
            e.iou[a][b] = box_iou(e.d[a]->bbox, e.g[b]->bbox, e.g[b]->iscrowd);
          } else {
            if (!e.g[b]->mask) throw InputError("ground truth annotation " + std::to_string(e.g[b]->id) + " has no RLE mask");
            e.iou[a][b] = rle_iou(*e.d[a]->mask, *e.g[b]->mask, e.g[b]->iscrowd);
          }
        }
      per.push_back(std::move(e));
    }
    for (std::size_t ai = 0; ai < A; ++ai) {
      const double lo = areas[ai][0], hi = areas[ai][1];
      std::vector<ImageEval> evals;
      for (const PerImage& e : per) {
        ImageEval ev;
        std::vector<char> ig(e.g.size());
        for (std::size_t b = 0; b < e.g.size(); ++b) ig[b] = e.g[b]->iscrowd || e.g[b]->area < lo || e.g[b]->area > hi;
        std::vector<std::size_t> order(e.g.size());
        std::iota(order.begin(), order.end(), 0);
        std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return ig[a] < ig[b]; });
        const std::size_t D = e.d.size(), G = e.g.size();
        ev.matched.assign(T, std::vector<char>(D, 0));
        ev.ignored.assign(T, std::vector<char>(D, 0));
        std::vector<std::vector<char>> gt_taken(T, std::vector<char>(G, 0));
        for (std::size_t t = 0; t < T; ++t)
          for (std::size_t a = 0; a < D; ++a) {
            double best = std::min(iou_thr[t], 1 - 1e-10);
            std::ptrdiff_t m = -1;
            for (std::size_t q = 0; q < G; ++q) {
              const std::size_t b = order[q];
              if (gt_taken[t][q] && !e.g[b]->iscrowd) continue;
              if (m > -1 && !ig[order[static_cast<std::size_t>(m)]] && ig[b]) break;
              if (e.iou[a][b] < best) continue;
              best = e.iou[a][b];
              m = static_cast<std::ptrdiff_t>(q);
            }
            if (m == -1) continue;
            ev.ignored[t][a] = ig[order[static_cast<std::size_t>(m)]];
            ev.matched[t][a] = 1;
            gt_taken[t][static_cast<std::size_t>(m)] = 1;
          }
        for (std::size_t a = 0; a < D; ++a) {
          const bool outside = e.d[a]->area < lo || e.d[a]->area > hi;
          for (std::size_t t = 0; t < T; ++t)
            if (!ev.matched[t][a] && outside) ev.ignored[t][a] = 1;
          ev.scores.push_back(e.d[a]->score);
        }
        for (std::size_t q = 0; q < G; ++q) ev.gt_ignored.push_back(ig[order[q]]);
        evals.push_back(std::move(ev));
      }
      for (std::size_t mi = 0; mi < M; ++mi) {
        const std::size_t cut = static_cast<std::size_t>(p.max_dets[mi]);
        // Every image's first `cut` detections, merged best first (stable: image order, then rank).
        struct Ref {
          double score;
          std::size_t e, a;
        };
        std::vector<Ref> all;
        std::size_t npig = 0;
        for (std::size_t ei = 0; ei < evals.size(); ++ei) {
          for (std::size_t a = 0; a < std::min(cut, evals[ei].scores.size()); ++a) all.push_back({evals[ei].scores[a], ei, a});
          for (const char g : evals[ei].gt_ignored) npig += g == 0;
        }
        if (npig == 0) continue;
        std::stable_sort(all.begin(), all.end(), [](const Ref& x, const Ref& y) { return x.score > y.score; });
        const std::size_t nd = all.size();
        for (std::size_t t = 0; t < T; ++t) {
          std::vector<double> rc(nd), pr(nd);
          double tp = 0, fp = 0;
          for (std::size_t i = 0; i < nd; ++i) {
            const ImageEval& ev = evals[all[i].e];
            const bool ign = ev.ignored[t][all[i].a], mt = ev.matched[t][all[i].a];
            if (mt && !ign) tp += 1;
            if (!mt && !ign) fp += 1;
            rc[i] = tp / static_cast<double>(npig);
            pr[i] = tp / (fp + tp + std::numeric_limits<double>::epsilon());
          }
          recall[ridx(t, k, ai, mi)] = nd ? rc[nd - 1] : 0;
          for (std::size_t i = nd; i-- > 1;)
            if (pr[i] > pr[i - 1]) pr[i - 1] = pr[i];
          for (std::size_t r = 0; r < R; ++r) {
            const std::size_t at = static_cast<std::size_t>(std::lower_bound(rc.begin(), rc.end(), rec_thr[r]) - rc.begin());
            precision[pidx(t, r, k, ai, mi)] = at < nd ? pr[at] : 0;
          }
        }
      }
    }
  }

  // COCOeval.summarize() over the categories in `ks`.
  auto summarize = [&](const std::vector<std::size_t>& ks) {
    auto mean = [](const std::vector<double>& v) {
      double s = 0;
      std::size_t n = 0;
      for (const double x : v)
        if (x > -1) s += x, ++n;
      return n ? s / static_cast<double>(n) : -1.0;
    };
    auto ap = [&](int t_only, std::size_t a, std::size_t m) {
      std::vector<double> v;
      for (std::size_t t = 0; t < T; ++t) {
        if (t_only >= 0 && t != static_cast<std::size_t>(t_only)) continue;
        for (std::size_t r = 0; r < R; ++r)
          for (const std::size_t k : ks) v.push_back(precision[pidx(t, r, k, a, m)]);
      }
      return mean(v);
    };
    auto ar = [&](std::size_t a, std::size_t m) {
      std::vector<double> v;
      for (std::size_t t = 0; t < T; ++t)
        for (const std::size_t k : ks) v.push_back(recall[ridx(t, k, a, m)]);
      return mean(v);
    };
    const std::size_t last = M - 1;
    // IoU 0.5 and 0.75 are thresholds 0 and 5.
    return std::array<double, 12>{ap(-1, 0, last), ap(0, 0, last), ap(5, 0, last), ap(-1, 1, last), ap(-1, 2, last),
                                  ap(-1, 3, last), ar(0, 0), ar(0, 1), ar(0, 2), ar(1, last), ar(2, last), ar(3, last)};
  };
  CocoEvalResult result;
  std::vector<std::size_t> all(K);
  std::iota(all.begin(), all.end(), 0);
  result.stats = summarize(all);
  for (std::size_t k = 0; k < K; ++k) result.per_category.emplace_back(cats[k], summarize({k}));
  return result;
}

}  // namespace grapebench
