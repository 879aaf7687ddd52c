#include "bench/scoring/coco_eval.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <set>
#include <stdexcept>
#include <unordered_map>

#include "synth/config.h"
#include "synth/rng.h"

#include <tbb/parallel_for.h>

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


}  // namespace

namespace {
// COCOeval's thresholds (np.linspace's values, so they compare as COCOeval's do) and area ranges.
std::vector<double> linspace(double lo, double hi, int n) {
  std::vector<double> t(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) t[static_cast<std::size_t>(i)] = i * ((hi - lo) / (n - 1)) + lo;
  t.back() = hi;
  return t;
}
constexpr std::array<std::array<double, 2>, 4> kAreas{{{0, 1e10}, {0, 32.0 * 32}, {32.0 * 32, 96.0 * 96}, {96.0 * 96, 1e10}}};
constexpr std::size_t kT = 10, kR = 101, kA = kAreas.size();
}  // namespace

CocoEvaluation coco_evaluate_images(const CocoGroundTruth& gt, const std::vector<CocoObject>& dets, const CocoEvalParams& p) {
  if (p.max_dets.size() != 3) throw std::invalid_argument("coco_evaluate: three max_dets");
  const std::vector<double> iou_thr = linspace(0.5, 0.95, static_cast<int>(kT));
  const int max_det = p.max_dets.back();
  CocoEvaluation out;
  out.max_dets = p.max_dets;
  // Images in id order, categories in id order (COCOeval's sorted imgIds and catIds).
  std::vector<std::int64_t> image_ids;
  for (const CocoImage& im : gt.images) image_ids.push_back(im.id);
  std::sort(image_ids.begin(), image_ids.end());
  out.images = image_ids.size();
  out.categories = gt.categories;
  std::sort(out.categories.begin(), out.categories.end(), [](const CocoCategory& a, const CocoCategory& b) { return a.id < b.id; });
  const std::size_t K = out.categories.size(), I = image_ids.size();
  std::map<std::pair<std::int64_t, int>, std::vector<const CocoObject*>> gts, dts;
  for (const CocoObject& g : gt.annotations) gts[{g.image_id, g.category_id}].push_back(&g);
  for (const CocoObject& d : dets) dts[{d.image_id, d.category_id}].push_back(&d);
  out.evals.resize(K * kA * I);

  for (std::size_t k = 0; k < K; ++k)
    for (std::size_t i = 0; i < I; ++i) {
      // The IoUs of each image once: detections best first (stable), cut at max_det.
      std::vector<const CocoObject*> g, d;
      const auto gi = gts.find({image_ids[i], out.categories[k].id});
      const auto di = dts.find({image_ids[i], out.categories[k].id});
      if (gi != gts.end()) g = gi->second;
      if (di != dts.end()) d = di->second;
      if (g.empty() && d.empty()) continue;
      std::stable_sort(d.begin(), d.end(), [](const CocoObject* a, const CocoObject* b) { return a->score > b->score; });
      if (d.size() > static_cast<std::size_t>(max_det)) d.resize(static_cast<std::size_t>(max_det));
      std::vector<std::vector<double>> iou(d.size(), std::vector<double>(g.size(), 0.0));  // [detection][ground truth]
      for (std::size_t a = 0; a < d.size(); ++a)
        for (std::size_t b = 0; b < g.size(); ++b) {
          if (p.type == CocoIouType::Bbox) {
            iou[a][b] = box_iou(d[a]->bbox, g[b]->bbox, g[b]->iscrowd);
          } else {
            if (!g[b]->mask) throw InputError("ground truth annotation " + std::to_string(g[b]->id) + " has no RLE mask");
            iou[a][b] = rle_iou(*d[a]->mask, *g[b]->mask, g[b]->iscrowd);
          }
        }
      for (std::size_t ai = 0; ai < kA; ++ai) {
        const double lo = kAreas[ai][0], hi = kAreas[ai][1];
        CocoImageEval& ev = out.evals[(k * kA + ai) * I + i];
        std::vector<char> ig(g.size());
        for (std::size_t b = 0; b < g.size(); ++b) ig[b] = g[b]->iscrowd || g[b]->area < lo || g[b]->area > hi;
        std::vector<std::size_t> order(g.size());
        std::iota(order.begin(), order.end(), 0);
        std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return ig[a] < ig[b]; });
        const std::size_t D = d.size(), G = g.size();
        ev.matched.assign(kT, std::vector<char>(D, 0));
        ev.ignored.assign(kT, std::vector<char>(D, 0));
        std::vector<std::vector<char>> gt_taken(kT, std::vector<char>(G, 0));
        for (std::size_t t = 0; t < kT; ++t)
          for (std::size_t a = 0; a < D; ++a) {
            double best = std::min(iou_thr[t], 1 - 1e-10);
            std::ptrdiff_t m = -1;
            for (std::size_t q = 0; q < G; ++q) {
              const std::size_t b = order[q];
              if (gt_taken[t][q] && !g[b]->iscrowd) continue;
              if (m > -1 && !ig[order[static_cast<std::size_t>(m)]] && ig[b]) break;
              if (iou[a][b] < best) continue;
              best = iou[a][b];
              m = static_cast<std::ptrdiff_t>(q);
            }
            if (m == -1) continue;
            ev.ignored[t][a] = ig[order[static_cast<std::size_t>(m)]];
            ev.matched[t][a] = 1;
            gt_taken[t][static_cast<std::size_t>(m)] = 1;
          }
        for (std::size_t a = 0; a < D; ++a) {
          const bool outside = d[a]->area < lo || d[a]->area > hi;
          for (std::size_t t = 0; t < kT; ++t)
            if (!ev.matched[t][a] && outside) ev.ignored[t][a] = 1;
          ev.scores.push_back(d[a]->score);
        }
        for (std::size_t q = 0; q < G; ++q) ev.gt_ignored.push_back(ig[order[q]]);
      }
    }
  return out;
}

CocoEvalResult coco_accumulate(const CocoEvaluation& e, const std::vector<std::size_t>& images, bool all_ranges) {
  const std::vector<double> rec_thr = linspace(0.0, 1.0, static_cast<int>(kR));
  const std::size_t K = e.categories.size(), M = e.max_dets.size(), I = e.images;
  // precision[t][r][k][a][m], recall[t][k][a][m]: -1 where undefined.
  auto pidx = [&](std::size_t t, std::size_t r, std::size_t k, std::size_t a, std::size_t m) {
    return (((t * kR + r) * K + k) * kA + a) * M + m;
  };
  auto ridx = [&](std::size_t t, std::size_t k, std::size_t a, std::size_t m) { return ((t * K + k) * kA + a) * M + m; };
  std::vector<double> precision(kT * kR * K * kA * M, -1.0), recall(kT * K * kA * M, -1.0);
  struct Ref {
    double score;
    const CocoImageEval* e;
    std::size_t a;
  };
  std::vector<Ref> all;
  std::vector<double> rc, pr;
  for (std::size_t k = 0; k < K; ++k)
    for (std::size_t ai = 0; ai < (all_ranges ? kA : 1); ++ai)
      for (std::size_t mi = all_ranges ? 0 : M - 1; mi < M; ++mi) {
        const std::size_t cut = static_cast<std::size_t>(e.max_dets[mi]);
        // Every image's first `cut` detections, merged best first (stable: image order, then rank).
        all.clear();
        std::size_t npig = 0;
        for (const std::size_t i : images) {
          const CocoImageEval& ev = e.evals[(k * kA + ai) * I + i];
          for (std::size_t a = 0; a < std::min(cut, ev.scores.size()); ++a) all.push_back({ev.scores[a], &ev, a});
          for (const char g : ev.gt_ignored) npig += g == 0;
        }
        if (npig == 0) continue;
        std::stable_sort(all.begin(), all.end(), [](const Ref& x, const Ref& y) { return x.score > y.score; });
        const std::size_t nd = all.size();
        rc.resize(nd), pr.resize(nd);
        for (std::size_t t = 0; t < kT; ++t) {
          double tp = 0, fp = 0;
          for (std::size_t i = 0; i < nd; ++i) {
            const bool ign = all[i].e->ignored[t][all[i].a], mt = all[i].e->matched[t][all[i].a];
            if (mt && !ign) tp += 1;
            if (!mt && !ign) fp += 1;
            rc[i] = tp / static_cast<double>(npig);
            pr[i] = tp / (fp + tp + std::numeric_limits<double>::epsilon());
          }
          recall[ridx(t, k, ai, mi)] = nd ? rc[nd - 1] : 0;
          for (std::size_t i = nd; i-- > 1;)
            if (pr[i] > pr[i - 1]) pr[i - 1] = pr[i];
          for (std::size_t r = 0; r < kR; ++r) {
            const std::size_t at = static_cast<std::size_t>(std::lower_bound(rc.begin(), rc.end(), rec_thr[r]) - rc.begin());
            precision[pidx(t, r, k, ai, mi)] = at < nd ? pr[at] : 0;
          }
        }
      }

  // COCOeval.summarize() over the categories in `ks`: means of the defined (> -1) values.
  auto summarize = [&](const std::vector<std::size_t>& ks) {
    auto ap = [&](int t_only, std::size_t a, std::size_t m) {
      double sum = 0;
      std::size_t n = 0;
      for (std::size_t t = 0; t < kT; ++t) {
        if (t_only >= 0 && t != static_cast<std::size_t>(t_only)) continue;
        for (std::size_t r = 0; r < kR; ++r)
          for (const std::size_t k : ks) {
            const double x = precision[pidx(t, r, k, a, m)];
            if (x > -1) sum += x, ++n;
          }
      }
      return n ? sum / static_cast<double>(n) : -1.0;
    };
    auto ar = [&](std::size_t a, std::size_t m) {
      double sum = 0;
      std::size_t n = 0;
      for (std::size_t t = 0; t < kT; ++t)
        for (const std::size_t k : ks) {
          const double x = recall[ridx(t, k, a, m)];
          if (x > -1) sum += x, ++n;
        }
      return n ? sum / static_cast<double>(n) : -1.0;
    };
    const std::size_t last = M - 1;
    // IoU 0.5 and 0.75 are thresholds 0 and 5; without all_ranges only what was accumulated.
    if (!all_ranges)
      return std::array<double, 12>{ap(-1, 0, last), ap(0, 0, last), ap(5, 0, last), -1, -1, -1, -1, -1, ar(0, last), -1, -1, -1};
    return std::array<double, 12>{ap(-1, 0, last), ap(0, 0, last), ap(5, 0, last), ap(-1, 1, last), ap(-1, 2, last),
                                  ap(-1, 3, last), ar(0, 0), ar(0, 1), ar(0, 2), ar(1, last), ar(2, last), ar(3, last)};
  };
  CocoEvalResult result;
  std::vector<std::size_t> every(K);
  std::iota(every.begin(), every.end(), 0);
  result.stats = summarize(every);
  for (std::size_t k = 0; k < K; ++k) result.per_category.emplace_back(e.categories[k], summarize({k}));
  return result;
}

CocoEvalResult coco_evaluate(const CocoGroundTruth& gt, const std::vector<CocoObject>& dets, const CocoEvalParams& p) {
  const CocoEvaluation e = coco_evaluate_images(gt, dets, p);
  std::vector<std::size_t> images(e.images);
  std::iota(images.begin(), images.end(), 0);
  return coco_accumulate(e, images, true);
}

namespace {

// AP and AP50 overall, then per category: [2 + 2K].
std::vector<double> ap_pair(const CocoEvalResult& r) {
  std::vector<double> v{r.stats[0], r.stats[1]};
  for (const auto& [c, s] : r.per_category) v.push_back(s[0]), v.push_back(s[1]);
  return v;
}

CocoIntervals to_intervals(const std::vector<std::vector<double>>& boot, std::size_t K, double level) {
  auto column = [&](std::size_t j) {
    std::vector<double> v;
    for (const auto& b : boot) v.push_back(b[j]);  // NaN: undefined in that resample, dropped
    return percentile_interval(v, level);
  };
  CocoIntervals out;
  out.ap = column(0), out.ap50 = column(1);
  for (std::size_t k = 0; k < K; ++k) out.per_category.push_back({column(2 + 2 * k), column(3 + 2 * k)});
  return out;
}

}  // namespace

namespace {

// Resample b's image positions: groups drawn with replacement, their images together
// (sorted: image order, as COCOeval's merge), from b's own stream so resamples run in
// parallel and stay identical at any thread count. No groups: each image alone.
std::vector<std::size_t> resample(std::size_t n, const std::vector<std::vector<std::size_t>>& groups, std::uint64_t seed,
                                  int b) {
  Rng rng(derive_seed(seed, static_cast<std::uint64_t>(b)));
  std::vector<std::size_t> images;
  if (groups.empty()) {
    images.resize(n);
    for (std::size_t& i : images) i = static_cast<std::size_t>(rng.next() % n);
  } else {
    for (std::size_t g = 0; g < groups.size(); ++g) {
      const auto& pick = groups[static_cast<std::size_t>(rng.next() % groups.size())];
      images.insert(images.end(), pick.begin(), pick.end());
    }
  }
  std::sort(images.begin(), images.end());
  return images;
}

}  // namespace

CocoIntervals coco_bootstrap(const CocoEvaluation& e, std::uint64_t seed, int resamples, double level,
                             const std::vector<std::vector<std::size_t>>& groups) {
  std::vector<std::vector<double>> boot(e.images > 0 ? static_cast<std::size_t>(resamples) : 0);
  tbb::parallel_for(std::size_t{0}, boot.size(), [&](std::size_t b) {
    std::vector<double> v = ap_pair(coco_accumulate(e, resample(e.images, groups, seed, static_cast<int>(b)), false));
    for (double& x : v)
      if (x <= -1) x = std::nan("");
    boot[b] = std::move(v);
  });
  return to_intervals(boot, e.categories.size(), level);
}

CocoIntervals coco_bootstrap_difference(const CocoEvaluation& a, const CocoEvaluation& b, std::uint64_t seed,
                                        int resamples, double level, const std::vector<std::vector<std::size_t>>& groups) {
  if (a.images != b.images || a.categories.size() != b.categories.size())
    throw std::invalid_argument("coco_bootstrap_difference: two evaluations of the same images and categories");
  std::vector<std::vector<double>> boot(a.images > 0 ? static_cast<std::size_t>(resamples) : 0);
  tbb::parallel_for(std::size_t{0}, boot.size(), [&](std::size_t r) {
    const std::vector<std::size_t> images = resample(a.images, groups, seed, static_cast<int>(r));
    std::vector<double> x = ap_pair(coco_accumulate(a, images, false)), y = ap_pair(coco_accumulate(b, images, false));
    for (std::size_t j = 0; j < x.size(); ++j) x[j] = x[j] > -1 && y[j] > -1 ? x[j] - y[j] : std::nan("");
    boot[r] = std::move(x);
  });
  return to_intervals(boot, a.categories.size(), level);
}

}  // namespace grapebench
