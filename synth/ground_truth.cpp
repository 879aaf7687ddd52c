#include "synth/ground_truth.h"

#include <CGAL/Min_sphere_of_spheres_d.h>
#include <CGAL/Min_sphere_of_spheres_d_traits_2.h>
#include <CGAL/Simple_cartesian.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>

#include "synth/ball_union.h"
#include "synth/config.h"
#include "synth/generate.h"
#include "synth/stem_geometry.h"

namespace grapebench {

namespace {

// Largest value of f over a circle (centre o, radius r, plane basis e1 e2): a fine
// scan then golden-section refinement of the best bracket.
template <class F>
double circle_max(const Vec3& o, double r, const Vec3& e1, const Vec3& e2, F f) {
  auto at = [&](double phi) { return f(o + r * (std::cos(phi) * e1 + std::sin(phi) * e2)); };
  const int n = 144;
  int best = 0;
  double bestv = -std::numeric_limits<double>::infinity();
  for (int k = 0; k < n; ++k) {
    const double v = at(2 * M_PI * k / n);
    if (v > bestv) {
      bestv = v;
      best = k;
    }
  }
  double a = 2 * M_PI * (best - 1) / n, b = 2 * M_PI * (best + 1) / n;
  const double g = 0.5 * (std::sqrt(5.0) - 1);
  for (int it = 0; it < 60; ++it) {
    const double x1 = b - g * (b - a), x2 = a + g * (b - a);
    if (at(x1) > at(x2))
      b = x2;
    else
      a = x1;
  }
  return std::max(bestv, at(0.5 * (a + b)));
}

}  // namespace

VolumeTerms solid_volume_terms(const Bunch& bunch) {
  VolumeTerms t;
  std::vector<Vec3> centres;
  std::vector<double> radii;
  for (const auto& b : bunch.berries) {
    centres.push_back(b.centre);
    radii.push_back(b.radius);
    t.berries_sum += 4.0 / 3.0 * M_PI * b.radius * b.radius * b.radius;
  }
  t.berries_union = union_of_balls_volume(centres, radii);
  for (const auto& s : bunch.stems) {
    t.stems += M_PI * s.radius * s.radius * (s.end - s.start).norm();
    if (s.parent >= 0) t.junction_overlap += junction_overlap_volume(s, bunch.stems[s.parent]);
    if (s.berry >= 0) t.pedicel_in_berry += pedicel_in_berry_volume(s, bunch.berries[s.berry]);
  }
  t.solid = t.berries_union + t.stems - t.junction_overlap - t.pedicel_in_berry;
  return t;
}

namespace {

// Seed 001's manual diameter: the smallest ring about the hanging bunch, i.e. the
// smallest enclosing circle of its horizontal projection: berries as discs, the stems
// other than the peduncle as discs of their radius at both ends (CGAL's exact
// min-sphere-of-spheres in 2D).
double ring_diameter(const Bunch& bunch) {
  using K = CGAL::Simple_cartesian<double>;
  using Traits = CGAL::Min_sphere_of_spheres_d_traits_2<K, double, CGAL::Tag_true>;
  std::vector<Traits::Sphere> discs;
  for (const auto& b : bunch.berries) discs.emplace_back(K::Point_2(b.centre.x(), b.centre.y()), b.radius);
  for (const auto& s : bunch.stems) {
    if (s.part == Part::Peduncle) continue;
    for (const Vec3& c : {s.start, s.end}) discs.emplace_back(K::Point_2(c.x(), c.y()), s.radius);
  }
  if (discs.empty()) return 0;
  CGAL::Min_sphere_of_spheres_d<Traits> ms(discs.begin(), discs.end());  // radius() is not const
  return 2 * ms.radius();
}

}  // namespace

namespace {

// Convex perimeter of the section {x : axes.col(k) . x = offset} of the bunch without
// its peduncle. Each berry disc is replaced by its inscribed and by its circumscribed
// 512-gon; their hull perimeters bracket the true one and err by -pi^2/6n^2 and
// +pi^2/3n^2 on the arcs, so (2 inner + outer)/3 cancels the error to O(n^-4)
// (Huygens' extrapolation).
double section_girth(const Bunch& bunch, const Eigen::Matrix3d& axes, int k, double offset) {
  const Vec3 u = axes.col(k), a = axes.col((k + 1) % 3), b = axes.col((k + 2) % 3);
  constexpr int kSides = 512;
  std::vector<Eigen::Vector2d> inner, outer;
  for (const auto& berry : bunch.berries) {
    const double d = berry.centre.dot(u) - offset;
    if (std::abs(d) >= berry.radius) continue;
    const double rho = std::sqrt(berry.radius * berry.radius - d * d);
    const Eigen::Vector2d c(berry.centre.dot(a), berry.centre.dot(b));
    for (int i = 0; i < kSides; ++i) {
      const double t = 2 * M_PI * i / kSides;
      const Eigen::Vector2d dir(std::cos(t), std::sin(t));
      inner.push_back(c + rho * dir);
      outer.push_back(c + rho / std::cos(M_PI / kSides) * dir);
    }
  }
  for (const auto& s : bunch.stems) {
    if (s.part == Part::Peduncle) continue;
    const Vec3 axis = s.end - s.start;
    const double len = axis.norm();
    const Vec3 dir = axis / len;
    if (std::abs(dir.dot(u)) < 1e-9) continue;  // parallel to the plane: a measure-zero strip
    Vec3 e1, e2;
    perpendicular_basis(dir, e1, e2);
    for (int i = 0; i < 64; ++i) {
      const double t = 2 * M_PI * i / 64;
      const Vec3 base = s.start + s.radius * (std::cos(t) * e1 + std::sin(t) * e2);
      const double along = (offset - base.dot(u)) / dir.dot(u);
      if (along < 0 || along > len) continue;
      const Vec3 x = base + along * dir;
      inner.emplace_back(x.dot(a), x.dot(b));
      outer.emplace_back(x.dot(a), x.dot(b));
    }
  }
  return (2 * convex_perimeter_2d(inner) + convex_perimeter_2d(outer)) / 3;
}

}  // namespace

BerryContacts berry_contacts(const Bunch& bunch) {
  // All pairs (n <= 1000 berries: at most 5e5 distance tests).
  BerryContacts c;
  std::vector<char> touched(bunch.berries.size(), 0);
  double depth_sum = 0;
  for (std::size_t i = 0; i < bunch.berries.size(); ++i) {
    const Berry& a = bunch.berries[i];
    for (std::size_t j = i + 1; j < bunch.berries.size(); ++j) {
      const Berry& b = bunch.berries[j];
      // Touching counts: the packing leaves berries at contact to within rounding.
      const double depth = a.radius + b.radius - (a.centre - b.centre).norm();
      if (depth <= -1e-9 * std::min(a.radius, b.radius)) continue;
      const double ratio = std::max(0.0, depth) / std::min(a.radius, b.radius);
      ++c.pairs;
      depth_sum += ratio;
      c.depth_max = std::max(c.depth_max, ratio);
      touched[i] = touched[j] = 1;
    }
  }
  if (!bunch.berries.empty()) {
    c.share_in_contact = static_cast<double>(std::count(touched.begin(), touched.end(), 1)) / bunch.berries.size();
  }
  if (c.pairs > 0) c.depth_mean = depth_sum / c.pairs;
  return c;
}

GroundTruth compute_ground_truth(const Bunch& bunch, double density) {
  if (bunch.berries.empty()) throw InputError("ground truth: the bunch has no berries");
  GroundTruth g;
  g.volume = solid_volume_terms(bunch);
  g.density = density;
  g.mass = density * g.volume.solid * 1e6;  // g/cm3 * cm3
  g.berry_count = static_cast<int>(bunch.berries.size());
  g.cutting_point = bunch.cutting_point;
  g.peduncle_direction = bunch.peduncle_direction;

  // PCA of the berries as solid balls: covariance of a ball is R^2/5 I.
  double wsum = 0;
  Vec3 mean = Vec3::Zero();
  for (const auto& b : bunch.berries) {
    const double w = std::pow(b.radius, 3);
    wsum += w;
    mean += w * b.centre;
  }
  mean /= wsum;
  Eigen::Matrix3d cov = Eigen::Matrix3d::Zero();
  for (const auto& b : bunch.berries) {
    const double w = std::pow(b.radius, 3) / wsum;
    const Vec3 d = b.centre - mean;
    cov += w * (d * d.transpose() + 0.2 * b.radius * b.radius * Eigen::Matrix3d::Identity());
  }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
  Eigen::Matrix3d axes;
  for (int k = 0; k < 3; ++k) {
    Vec3 a = eig.eigenvectors().col(2 - k);  // decreasing eigenvalue
    int big = 0;
    a.cwiseAbs().maxCoeff(&big);
    if (a[big] < 0) a = -a;  // deterministic sign
    axes.col(k) = a;
  }
  axes.col(2) = axes.col(0).cross(axes.col(1));
  g.pca_centre = mean;
  g.pca_axes = axes;

  // Exact extents of the body (all but the peduncle) along a direction u.
  auto extent = [&](const Vec3& u) {
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (const auto& b : bunch.berries) {
      lo = std::min(lo, b.centre.dot(u) - b.radius);
      hi = std::max(hi, b.centre.dot(u) + b.radius);
    }
    for (const auto& s : bunch.stems) {
      if (s.part == Part::Peduncle) continue;
      const Vec3 d = (s.end - s.start).normalized();
      const double rim = s.radius * std::sqrt(std::max(0.0, 1 - std::pow(d.dot(u), 2)));
      for (const Vec3& c : {s.start, s.end}) {
        lo = std::min(lo, c.dot(u) - rim);
        hi = std::max(hi, c.dot(u) + rim);
      }
    }
    return std::pair{lo, hi};
  };
  Vec3 mid;
  for (int k = 0; k < 3; ++k) {
    const auto [lo, hi] = extent(axes.col(k));
    g.pca_extent[k] = hi - lo;
    mid[k] = 0.5 * (lo + hi);
  }
  for (int k = 0; k < 3; ++k) g.section_perimeter[k] = section_girth(bunch, axes, k, mid[k]);
  const auto [zlo, zhi] = extent(Vec3::UnitZ());
  g.height = zhi - zlo;
  g.height_from_cutting_point = bunch.cutting_point.z() - zlo;
  const auto [xlo, xhi] = extent(Vec3::UnitX());
  const auto [ylo, yhi] = extent(Vec3::UnitY());
  g.row_width = xhi - xlo;
  g.row_depth = yhi - ylo;

  // Maximum diameter about the vertical through the cutting point.
  const Eigen::Vector2d axis_xy = bunch.cutting_point.head<2>();
  auto radial = [&](const Vec3& x) { return (x.head<2>() - axis_xy).norm(); };
  double rmax = 0;
  for (const auto& b : bunch.berries) rmax = std::max(rmax, radial(b.centre) + b.radius);
  for (const auto& s : bunch.stems) {
    if (s.part == Part::Peduncle) continue;
    const Vec3 d = (s.end - s.start).normalized();
    Vec3 e1, e2;
    perpendicular_basis(d, e1, e2);
    for (const Vec3& c : {s.start, s.end}) rmax = std::max(rmax, circle_max(c, s.radius, e1, e2, radial));
  }
  g.max_diameter = 2 * rmax;
  g.ring_diameter = ring_diameter(bunch);

  envelope_bounds(bunch, g.envelope_lower, g.envelope_upper);
  g.envelope_volume = 0.5 * (g.envelope_lower + g.envelope_upper);
  g.compactness = g.volume.solid / g.envelope_volume;

  const BerryContacts contacts = berry_contacts(bunch);
  g.contact_pairs = contacts.pairs;
  g.berries_in_contact = contacts.share_in_contact;
  g.contact_depth_mean = contacts.depth_mean;
  g.contact_depth_max = contacts.depth_max;

  // Asymmetry: horizontal principal axes of the berries (weights r^3, as the PCA frame).
  if (bunch.berries.size() >= 2) {
    Eigen::Vector2d centre2 = Eigen::Vector2d::Zero();
    double weight = 0;
    for (const auto& b : bunch.berries) {
      const double w = b.radius * b.radius * b.radius;
      centre2 += w * b.centre.head<2>();
      weight += w;
    }
    centre2 /= weight;
    Eigen::Matrix2d cov2 = Eigen::Matrix2d::Zero();
    for (const auto& b : bunch.berries) {
      const Eigen::Vector2d d = b.centre.head<2>() - centre2;
      cov2 += b.radius * b.radius * b.radius * d * d.transpose();
    }
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(cov2);
    double span[2];
    for (int k = 0; k < 2; ++k) {
      const Eigen::Vector2d u = es.eigenvectors().col(k);
      double lo = std::numeric_limits<double>::infinity(), hi = -lo;
      for (const auto& b : bunch.berries) {
        lo = std::min(lo, b.centre.head<2>().dot(u) - b.radius);
        hi = std::max(hi, b.centre.head<2>().dot(u) + b.radius);
      }
      span[k] = hi - lo;
    }
    g.horizontal_extent_ratio = std::min(span[0], span[1]) / std::max(span[0], span[1]);
  }
  if (bunch.wing >= 0 && !bunch.berries.empty()) {
    int on_wing = 0;
    for (const auto& b : bunch.berries) on_wing += b.pedicel >= 0 && grapebench::on_wing(bunch, b.pedicel);
    g.wing_berry_share = static_cast<double>(on_wing) / bunch.berries.size();
  }
  if (bunch.bend >= 0) {
    const Stem& s = bunch.stems[static_cast<std::size_t>(bunch.bend)];
    const Stem& above = bunch.stems[static_cast<std::size_t>(s.parent)];
    const double c = (s.end - s.start).normalized().dot((above.end - above.start).normalized());
    g.bend_angle = std::acos(std::clamp(c, -1.0, 1.0)) * 180 / M_PI;
  }

  // Bounding box of the whole solid.
  g.bbox_min = Vec3::Constant(std::numeric_limits<double>::infinity());
  g.bbox_max = -g.bbox_min;
  for (int k = 0; k < 3; ++k) {
    const Vec3 u = Vec3::Unit(k);
    for (const auto& b : bunch.berries) {
      g.bbox_min[k] = std::min(g.bbox_min[k], b.centre[k] - b.radius);
      g.bbox_max[k] = std::max(g.bbox_max[k], b.centre[k] + b.radius);
    }
    for (const auto& s : bunch.stems) {
      const Vec3 d = (s.end - s.start).normalized();
      const double rim = s.radius * std::sqrt(std::max(0.0, 1 - d[k] * d[k]));
      for (const Vec3& c : {s.start, s.end}) {
        g.bbox_min[k] = std::min(g.bbox_min[k], c.dot(u) - rim);
        g.bbox_max[k] = std::max(g.bbox_max[k], c.dot(u) + rim);
      }
    }
  }
  return g;
}

}  // namespace grapebench
