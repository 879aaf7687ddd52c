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
