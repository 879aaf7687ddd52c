// A k-d tree over a point cloud (nanoflann, Debian's libnanoflann-dev), for radius and
// nearest-neighbour queries of the per-point steps (seed 004's features and CRF) and
// of ICP's correspondences.
// The cloud must outlive the index; queries are const and safe from many threads.
#pragma once

#include <cstdint>
#include <memory>
#include <nanoflann.hpp>
#include <utility>
#include <vector>

#include "algorithms/point_cloud.h"

namespace grapebench {

class PointIndex {
 public:
  explicit PointIndex(const PointCloud& cloud)
      : adaptor_{&cloud}, tree_(3, adaptor_, nanoflann::KDTreeSingleIndexAdaptorParams(16)) {
    tree_.buildIndex();
  }
  PointIndex(const PointIndex&) = delete;
  PointIndex& operator=(const PointIndex&) = delete;

  // Calls visit(index, squared distance) for every point strictly within `radius` (m)
  // of q, in the tree's order (deterministic for a given cloud).
  template <class Visit>
  void for_each_within(const Vec3& q, double radius, Visit&& visit) const {
    Visitor<Visit> v{radius * radius, visit};
    const double query[3] = {q.x(), q.y(), q.z()};
    tree_.findNeighbors(v, query, nanoflann::SearchParams());
  }

  // The nearest point strictly within `radius` (m) of q as (index, squared distance), or
  // index -1 when there is none. The search is pruned at the radius from the start.
  std::pair<std::int64_t, double> nearest_within(const Vec3& q, double radius) const {
    Nearest best{radius * radius, -1};
    const double query[3] = {q.x(), q.y(), q.z()};
    tree_.findNeighbors(best, query, nanoflann::SearchParams());
    return {best.index, best.d2};
  }

  // Up to k nearest points (index, squared distance), nearest first, ties by index.
  std::vector<std::pair<std::uint32_t, double>> nearest(const Vec3& q, std::size_t k) const {
    std::vector<std::uint32_t> idx(k);
    std::vector<double> d2(k);
    const double query[3] = {q.x(), q.y(), q.z()};
    const std::size_t n = tree_.knnSearch(query, k, idx.data(), d2.data());
    std::vector<std::pair<std::uint32_t, double>> out;
    out.reserve(n);
    for (std::size_t i = 0; i < n; ++i) out.emplace_back(idx[i], d2[i]);
    return out;
  }

 private:
  struct Adaptor {
    const PointCloud* cloud;
    std::size_t kdtree_get_point_count() const { return static_cast<std::size_t>(cloud->rows()); }
    double kdtree_get_pt(std::size_t i, std::size_t d) const {
      return (*cloud)(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(d));
    }
    template <class Box>
    bool kdtree_get_bbox(Box&) const {
      return false;
    }
  };
  template <class Visit>
  struct Visitor {
    double radius2;
    Visit& visit;
    bool full() const { return true; }
    double worstDist() const { return radius2; }
    bool addPoint(double d2, std::uint32_t i) {
      if (d2 < radius2) visit(i, d2);
      return true;
    }
  };
  struct Nearest {
    double d2;
    std::int64_t index;
    bool full() const { return true; }
    double worstDist() const { return d2; }
    bool addPoint(double dist2, std::uint32_t i) {
      if (dist2 < d2 || (dist2 == d2 && index >= 0 && i < index)) d2 = dist2, index = i;
      return true;
    }
  };
  using Tree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, Adaptor>, Adaptor, 3,
                                                   std::uint32_t>;
  Adaptor adaptor_;
  Tree tree_;
};

}  // namespace grapebench
