#include "synth/ball_union.h"

#include <algorithm>
#include <cmath>

namespace grapebench {

ConvexPolyhedron make_box(const Vec3& c, double h) {
  ConvexPolyhedron p;
  for (int axis = 0; axis < 3; ++axis) {
    for (int sign : {-1, 1}) {
      Vec3 n = Vec3::Zero();
      n[axis] = sign;
      const int u = (axis + 1) % 3, v = (axis + 2) % 3;
      PolyFace f;
      f.normal = n;
      // Corners in counter-clockwise order seen along +n.
      const double su[4] = {-1, 1, 1, -1}, sv[4] = {-1, -1, 1, 1};
      for (int k = 0; k < 4; ++k) {
        Vec3 x = c;
        x[axis] += sign * h;
        x[u] += su[k] * h;
        x[v] += sv[k] * h * sign;
        f.vertices.push_back(x);
      }
      p.faces.push_back(std::move(f));
    }
  }
  return p;
}

void clip(ConvexPolyhedron& poly, const HalfSpace& h, int tag) {
  double scale = 0;
  for (const auto& f : poly.faces) {
    for (const auto& v : f.vertices) scale = std::max(scale, v.cwiseAbs().maxCoeff());
  }
  const double eps = 1e-14 * std::max(scale, 1e-300);
  std::vector<PolyFace> kept;
  std::vector<Vec3> cut;
  for (auto& f : poly.faces) {
    const std::size_t m = f.vertices.size();
    std::vector<double> dist(m);
    bool any_out = false, any_in = false;
    for (std::size_t k = 0; k < m; ++k) {
      dist[k] = h.n.dot(f.vertices[k]) - h.offset;
      if (dist[k] > eps) any_out = true;
      else any_in = true;
    }
    if (!any_out) {
      for (std::size_t k = 0; k < m; ++k) {
        if (std::abs(dist[k]) <= eps) cut.push_back(f.vertices[k]);
      }
      kept.push_back(std::move(f));
      continue;
    }
    if (!any_in) continue;
    PolyFace g;
    g.normal = f.normal;
    g.tag = f.tag;
    for (std::size_t k = 0; k < m; ++k) {
      const Vec3& a = f.vertices[k];
      const Vec3& b = f.vertices[(k + 1) % m];
      const bool ain = dist[k] <= eps, bin = dist[(k + 1) % m] <= eps;
      if (ain) g.vertices.push_back(a);
      if (ain && std::abs(dist[k]) <= eps) cut.push_back(a);
      if (ain != bin && std::abs(dist[k]) > eps && std::abs(dist[(k + 1) % m]) > eps) {
        // Interpolate from the lexicographically smaller end so the two faces that
        // share this edge compute the very same point.
        const bool swap = std::lexicographical_compare(b.data(), b.data() + 3, a.data(), a.data() + 3);
        const Vec3& p0 = swap ? b : a;
        const Vec3& p1 = swap ? a : b;
        const double d0 = swap ? dist[(k + 1) % m] : dist[k];
        const double d1 = swap ? dist[k] : dist[(k + 1) % m];
        const Vec3 x = p0 + (d0 / (d0 - d1)) * (p1 - p0);
        g.vertices.push_back(x);
        cut.push_back(x);
      }
    }
    if (g.vertices.size() >= 3) kept.push_back(std::move(g));
  }
  poly.faces = std::move(kept);
  if (poly.faces.empty()) return;
  // Cap: the cut points form a convex polygon in the plane; order them by angle.
  std::vector<Vec3> pts;
  for (const auto& x : cut) {
    bool dup = false;
    for (const auto& y : pts) dup = dup || (x - y).squaredNorm() <= 1e-24 * (scale * scale + 1e-300);
    if (!dup) pts.push_back(x);
  }
  if (pts.size() < 3) return;
  Vec3 centroid = Vec3::Zero();
  for (const auto& x : pts) centroid += x;
  centroid /= static_cast<double>(pts.size());
  const Vec3 helper = std::abs(h.n.x()) < 0.6 ? Vec3::UnitX() : Vec3::UnitY();
  const Vec3 e1 = h.n.cross(helper).normalized(), e2 = h.n.cross(e1);
  std::vector<std::pair<double, Vec3>> ordered;
  for (const auto& x : pts) {
    const Vec3 r = x - centroid;
    ordered.emplace_back(std::atan2(r.dot(e2), r.dot(e1)), x);
  }
  std::sort(ordered.begin(), ordered.end(),
            [](const auto& a, const auto& b) { return a.first < b.first; });
  PolyFace capf;
  capf.normal = h.n;
  capf.tag = tag;
  for (const auto& [angle, x] : ordered) capf.vertices.push_back(x);
  poly.faces.push_back(std::move(capf));
}

double polyhedron_volume(const ConvexPolyhedron& poly) {
  if (poly.empty()) return 0;
  const Vec3 o = poly.faces[0].vertices[0];
  double v = 0;
  for (const auto& f : poly.faces) {
    for (std::size_t k = 1; k + 1 < f.vertices.size(); ++k) {
      v += (f.vertices[0] - o).dot((f.vertices[k] - o).cross(f.vertices[k + 1] - o));
    }
  }
  return v / 6.0;
}

namespace {

// Integral of g(r) = min(1, R/sqrt(r^2 + h^2))^3 over the right triangle with the
// right angle at distance d from the origin (the foot m of the origin on an edge
// line) and legs d and |t|; odd in t. Polar integration in the face plane:
//   inner(theta) = int_0^{d/cos theta} g(r) r dr, closed form on either side of the
//   sphere's trace radius a = sqrt(R^2 - h^2);
//   int dtheta / sqrt(d^2/cos^2 theta + h^2) = asin(|h| sin theta / sqrt(d^2+h^2)) / |h|.
double right_triangle_integral(double d, double t, double h2, double R) {
  if (t < 0) return -right_triangle_integral(d, -t, h2, R);
  if (t == 0 || d <= 0) return 0;
  const double theta_end = std::atan2(t, d);
  const double a2 = R * R - h2;
  double theta_split = 0;  // below it, the whole radial segment lies inside the ball
  if (a2 > d * d) theta_split = std::min(theta_end, std::acos(d / std::sqrt(a2)));
  double value = 0.5 * d * d * std::tan(theta_split);
  if (theta_split < theta_end) {
    const double habs = std::sqrt(h2);
    const double R3 = R * R * R;
    const double c0 = a2 > 0 ? 0.5 * a2 + R * R : R3 / habs;
    const double D = std::sqrt(d * d + h2);
    auto F = [&](double th) {
      const double s = std::sin(th);
      return habs > 1e-12 * D ? std::asin(std::min(1.0, habs * s / D)) / habs : s / D;
    };
    value += c0 * (theta_end - theta_split) - R3 * (F(theta_end) - F(theta_split));
  }
  return value;
}

}  // namespace

double ball_polyhedron_volume(const Vec3& c, double R, const ConvexPolyhedron& poly) {
  double v = 0;
  for (const auto& f : poly.faces) {
    const Vec3& n = f.normal;
    const double h = n.dot(f.vertices[0] - c);  // > 0 when c is on the inner side
    const Vec3 q = c + h * n;
    const Vec3 helper = std::abs(n.x()) < 0.6 ? Vec3::UnitX() : Vec3::UnitY();
    const Vec3 e1 = n.cross(helper).normalized(), e2 = n.cross(e1);
    const double h2 = h * h;
    double area = 0;
    const std::size_t m = f.vertices.size();
    for (std::size_t k = 0; k < m; ++k) {
      const Vec3 pa = f.vertices[k] - q, pb = f.vertices[(k + 1) % m] - q;
      const Eigen::Vector2d a(pa.dot(e1), pa.dot(e2)), b(pb.dot(e1), pb.dot(e2));
      const Eigen::Vector2d ab = b - a;
      const double len = ab.norm();
      if (len <= 0) continue;
      const Eigen::Vector2d u = ab / len;
      const double ta = a.dot(u), tb = b.dot(u);
      const Eigen::Vector2d mfoot = a - ta * u;
      const double cross = mfoot.x() * u.y() - mfoot.y() * u.x();
      const double d = mfoot.norm();
      const double sign = cross >= 0 ? 1.0 : -1.0;
      area += sign * (right_triangle_integral(d, tb, h2, R) - right_triangle_integral(d, ta, h2, R));
    }
    v += h / 3.0 * area;
  }
  return v;
}

bool power_cell_halfspaces(const std::vector<Vec3>& centres, const std::vector<double>& radii,
                           int i, std::vector<HalfSpace>& out, std::vector<int>* neighbours) {
  out.clear();
  if (neighbours) neighbours->clear();
  const Vec3& ci = centres[i];
  const double Ri = radii[i];
  for (int j = 0; j < static_cast<int>(centres.size()); ++j) {
    if (j == i) continue;
    const Vec3 delta = centres[j] - ci;
    const double D = delta.norm();
    const double Rj = radii[j];
    if (D >= Ri + Rj) continue;  // disjoint or tangent: the radical plane misses ball i
    if (D <= 1e-12 * (Ri + Rj)) {
      if (Rj > Ri || (Rj == Ri && j < i)) return false;  // a coincident twin owns it
      continue;
    }
    // pow_i(y) <= pow_j(y)  <=>  2 y·delta <= D^2 + Ri^2 - Rj^2  (y relative to ci)
    out.push_back({delta / D, (D * D + Ri * Ri - Rj * Rj) / (2 * D)});
    if (neighbours) neighbours->push_back(j);
  }
  return true;
}

double power_piece_volume(const std::vector<Vec3>& centres, const std::vector<double>& radii,
                          int i, const std::vector<HalfSpace>& extra) {
  std::vector<HalfSpace> hs;
  if (!power_cell_halfspaces(centres, radii, i, hs)) return 0;
  hs.insert(hs.end(), extra.begin(), extra.end());
  const double R = radii[i];
  ConvexPolyhedron cell = make_box(Vec3::Zero(), R * 1.01);
  int tag = 0;
  for (const auto& h : hs) {
    if (h.offset >= R) { ++tag; continue; }  // the plane misses the ball
    if (h.offset <= -R) return 0;            // the whole ball is cut away
    clip(cell, h, tag++);
    if (cell.empty()) return 0;
  }
  return ball_polyhedron_volume(Vec3::Zero(), R, cell);
}

double union_of_balls_volume(const std::vector<Vec3>& centres, const std::vector<double>& radii) {
  double v = 0;
  for (int i = 0; i < static_cast<int>(centres.size()); ++i) {
    v += power_piece_volume(centres, radii, i);
  }
  return v;
}

}  // namespace grapebench
