#include "bench/scoring/detections.h"

#include "bench/scoring/rates.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numeric>

namespace grapebench {

namespace {

// Precision, recall, F1 and the mean errors from the counts and error sums.
void finish(DetectionScore& s, double centre_sum, double radius_sum, double radius_abs_sum) {
  s.false_positives = s.detections - s.matched;
  s.precision = ratio(s.matched, s.detections);
  s.recall = ratio(s.visible_found, s.visible);
  s.f1 = std::isfinite(s.precision) && std::isfinite(s.recall) && s.precision + s.recall > 0
             ? 2 * s.precision * s.recall / (s.precision + s.recall)
             : kNaN;
  s.centre_error_mean = ratio(centre_sum, s.matched);
  s.radius_error_mean = ratio(radius_sum, s.matched);
  s.radius_error_mae = ratio(radius_abs_sum, s.matched);
}

}  // namespace

std::string DetectionMatch::describe() const {
  char b[64];
  if (rule == Rule::DiscIou) {
    std::snprintf(b, sizeof b, "disc IoU >= %g", threshold);
  } else {
    std::snprintf(b, sizeof b, "centre within %g x the object's radius", threshold);
  }
  return b;
}

double disc_iou(const Circle& a, const Circle& b) {
  const double d = std::hypot(a.x - b.x, a.y - b.y), r1 = a.r, r2 = b.r;
  if (!(r1 > 0 && r2 > 0)) return 0;
  const double area1 = M_PI * r1 * r1, area2 = M_PI * r2 * r2;
  double inter = 0;
  if (d >= r1 + r2) {
    inter = 0;
  } else if (d <= std::abs(r1 - r2)) {
    inter = std::min(area1, area2);
  } else {
    const double a1 = std::acos(std::clamp((d * d + r1 * r1 - r2 * r2) / (2 * d * r1), -1.0, 1.0));
    const double a2 = std::acos(std::clamp((d * d + r2 * r2 - r1 * r1) / (2 * d * r2), -1.0, 1.0));
    const double k = (-d + r1 + r2) * (d + r1 - r2) * (d - r1 + r2) * (d + r1 + r2);
    inter = r1 * r1 * a1 + r2 * r2 * a2 - 0.5 * std::sqrt(std::max(0.0, k));
  }
  return inter / (area1 + area2 - inter);
}

DetectionScore score_detections(const std::vector<Detection>& detections, const std::vector<TruthObject>& truth,
                                const DetectionMatch& rule) {
  DetectionScore s;
  s.detections = static_cast<int>(detections.size());
  s.match.assign(detections.size(), -1);
  for (const auto& t : truth) s.visible += t.visible;
  std::vector<std::size_t> order(detections.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return detections[a].score > detections[b].score; });
  std::vector<bool> taken(truth.size(), false);
  double centre_sum = 0, radius_sum = 0, radius_abs_sum = 0;
  for (const std::size_t i : order) {
    const Circle& c = detections[i].circle;
    int best = -1;
    double best_value = 0;
    for (std::size_t j = 0; j < truth.size(); ++j) {
      if (taken[j]) continue;
      const Circle& o = truth[j].circle;
      double value = 0;  // larger is better
      if (rule.rule == DetectionMatch::Rule::DiscIou) {
        value = disc_iou(c, o);
        if (value < rule.threshold) continue;
      } else {
        const double d = std::hypot(c.x - o.x, c.y - o.y);
        if (d > rule.threshold * o.r) continue;
        value = 1 / (1 + d);
      }
      if (best < 0 || value > best_value) {
        best = static_cast<int>(j);
        best_value = value;
      }
    }
    if (best < 0) continue;
    taken[static_cast<std::size_t>(best)] = true;
    s.match[i] = best;
    ++s.matched;
    const Circle& o = truth[static_cast<std::size_t>(best)].circle;
    s.visible_found += truth[static_cast<std::size_t>(best)].visible;
    centre_sum += std::hypot(c.x - o.x, c.y - o.y);
    radius_sum += c.r - o.r;
    radius_abs_sum += std::abs(c.r - o.r);
  }
  finish(s, centre_sum, radius_sum, radius_abs_sum);
  return s;
}

DetectionScore pool_detection_scores(const std::vector<DetectionScore>& scores) {
  DetectionScore s;
  double centre_sum = 0, radius_sum = 0, radius_abs_sum = 0;
  for (const auto& x : scores) {
    s.detections += x.detections;
    s.matched += x.matched;
    s.visible += x.visible;
    s.visible_found += x.visible_found;
    if (x.matched > 0) {
      centre_sum += x.centre_error_mean * x.matched;
      radius_sum += x.radius_error_mean * x.matched;
      radius_abs_sum += x.radius_error_mae * x.matched;
    }
  }
  finish(s, centre_sum, radius_sum, radius_abs_sum);
  return s;
}

}  // namespace grapebench
