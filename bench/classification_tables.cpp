#include "bench/classification_tables.h"

#include <algorithm>
#include <map>
#include <tuple>

namespace grapebench {

bool is_classification_row(const std::string& q) {
  for (const char* p : {"auc_", "iou_", "precision_", "recall_"}) {
    if (q.rfind(p, 0) == 0) return true;
  }
  return q == "accuracy" || q == "miou" || q == "berry_tpr" || q == "berry_fpr";
}

std::vector<std::pair<std::string, std::vector<double>>> mean_roc(const std::vector<CaseResult>& cases, int condition,
                                                                  const std::string& class_name) {
  std::vector<std::pair<std::string, std::vector<double>>> out;
  std::vector<int> count;
  for (const CaseResult& c : cases) {
    if (c.condition != condition) continue;
    for (const RocSamples& s : c.roc) {
      if (s.class_name != class_name) continue;
      auto it = std::find_if(out.begin(), out.end(), [&](const auto& e) { return e.first == s.estimator; });
      if (it == out.end()) {
        out.emplace_back(s.estimator, std::vector<double>(s.tpr.size(), 0.0));
        count.push_back(0);
        it = out.end() - 1;
      }
      for (std::size_t g = 0; g < s.tpr.size() && g < it->second.size(); ++g) it->second[g] += s.tpr[g];
      ++count[static_cast<std::size_t>(it - out.begin())];
    }
  }
  for (std::size_t e = 0; e < out.size(); ++e) {
    for (double& v : out[e].second) v /= count[e];
  }
  return out;
}

std::vector<PooledConfusion> pooled_confusion(const std::vector<CaseResult>& cases, int condition) {
  std::vector<PooledConfusion> out;
  for (const CaseResult& c : cases) {
    if (c.condition != condition) continue;
    for (const ConfusionCounts& m : c.confusion) {
      auto it = std::find_if(out.begin(), out.end(), [&](const auto& e) { return e.estimator == m.estimator; });
      if (it == out.end()) {
        out.push_back({m.estimator, m.classes, std::vector<long long>(m.counts.size(), 0), 0, 0});
        it = out.end() - 1;
      }
      if (it->counts.size() != m.counts.size()) continue;  // another class set: not pooled
      for (std::size_t i = 0; i < m.counts.size(); ++i) it->counts[i] += m.counts[i];
    }
  }
  for (PooledConfusion& p : out) {
    const std::size_t k = p.classes.size();
    long long total = 0, right = 0;
    double iou_sum = 0;
    int defined = 0;
    for (std::size_t a = 0; a < k; ++a) {
      long long row = 0, col = 0;
      for (std::size_t b = 0; b < k; ++b) row += p.counts[a * k + b], col += p.counts[b * k + a];
      total += row;
      right += p.counts[a * k + a];
      const long long uni = row + col - p.counts[a * k + a];
      if (uni > 0) iou_sum += static_cast<double>(p.counts[a * k + a]) / static_cast<double>(uni), ++defined;
    }
    p.accuracy = total ? static_cast<double>(right) / static_cast<double>(total) : NAN;
    p.miou = defined ? iou_sum / defined : NAN;
  }
  return out;
}

std::vector<ClassificationCell> classification_cells(const std::vector<CaseResult>& cases,
                                                     const std::vector<std::string>& labels) {
  std::vector<ClassificationCell> cells;
  std::map<std::tuple<int, std::string, std::string>, std::size_t> where;
  for (const CaseResult& c : cases) {
    for (const EstimateRow& r : c.rows) {
      if (!is_classification_row(r.quantity)) continue;
      const auto key = std::make_tuple(c.condition, r.estimator, r.quantity);
      auto it = where.find(key);
      if (it == where.end()) {
        const std::string label =
            c.condition >= 0 && static_cast<std::size_t>(c.condition) < labels.size() ? labels[c.condition] : "";
        it = where.emplace(key, cells.size()).first;
        cells.push_back({label, r.estimator, r.quantity, 0, 0, 0, 0});
      }
      if (!r.ok) continue;
      ClassificationCell& cell = cells[it->second];
      cell.min = cell.cases ? std::min(cell.min, r.estimate) : r.estimate;
      cell.max = cell.cases ? std::max(cell.max, r.estimate) : r.estimate;
      cell.mean += r.estimate;
      ++cell.cases;
    }
  }
  for (ClassificationCell& cell : cells) cell.mean = cell.cases ? cell.mean / cell.cases : NAN;
  return cells;
}

}  // namespace grapebench
