#include "algorithms/poisson_screened.h"

#include "algorithms/grid_contour.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>

namespace grapebench {

namespace {

// The unknown chi lives on the nodes of a regular grid (trilinear between them).
// Energy (Kazhdan & Hoppe 2013 Eq. 4, discretised):
//   sum over grid edges e of h^3 ((chi_head - chi_tail) / h - V_e)^2
//   + w * sum_i a_i chi(p_i)^2,                       w = alpha / h_finest
// where V_e is the splatted field sum_i a_i n_i (edge's axis component, trilinear on
// the lattice of edge midpoints) per unit volume. Its minimiser solves
//   (h L + w B^T diag(a) B) chi = b,   b_node = (1/h) sum_e (+-1) splat_e,
// L the grid graph's Laplacian (free, Neumann, boundary) and B the trilinear
// interpolation at the points. chi rises by ~1 across the surface, outward.

struct Grid {
  std::array<int, 3> n{};  // nodes per axis
  double h = 0;            // m
  Vec3 origin = Vec3::Zero();
  std::size_t size() const { return static_cast<std::size_t>(n[0]) * static_cast<std::size_t>(n[1]) * static_cast<std::size_t>(n[2]); }
  std::size_t index(int x, int y, int z) const {
    return (static_cast<std::size_t>(z) * static_cast<std::size_t>(n[1]) + static_cast<std::size_t>(y)) * static_cast<std::size_t>(n[0]) +
           static_cast<std::size_t>(x);
  }
  // Offset of corner c (bit 0: +x, bit 1: +y, bit 2: +z) from a cell's lowest node.
  std::size_t corner(int c) const {
    return static_cast<std::size_t>(c & 1) + static_cast<std::size_t>((c >> 1) & 1) * static_cast<std::size_t>(n[0]) +
           static_cast<std::size_t>((c >> 2) & 1) * static_cast<std::size_t>(n[0]) * static_cast<std::size_t>(n[1]);
  }
};

// A point's trilinear footprint on a lattice of spacing h: its cell's lowest node and
// the eight corner weights (summing to 1).
struct Footprint {
  std::size_t base = 0;
  std::array<double, 8> w{};
  double weight = 0;  // screening weight of the point, w * a_i
};

// `shift` (in steps) moves the lattice, e.g. by half a step along an axis for edge midpoints;
// `cells` is the number of cells per axis on that lattice.
Footprint footprint(const Grid& g, const Vec3& p, const Vec3& shift, const std::array<int, 3>& cells) {
  std::array<double, 3> t{};
  std::size_t base = 0;
  const std::array<std::size_t, 3> stride{g.corner(1), g.corner(2), g.corner(4)};
  for (int k = 0; k < 3; ++k) {
    const double u = (p(k) - g.origin(k)) / g.h - shift(k);
    const int i = std::clamp(static_cast<int>(std::floor(u)), 0, cells[static_cast<std::size_t>(k)] - 1);
    t[static_cast<std::size_t>(k)] = std::clamp(u - i, 0.0, 1.0);
    base += static_cast<std::size_t>(i) * stride[static_cast<std::size_t>(k)];
  }
  Footprint f;
  f.base = base;
  for (int c = 0; c < 8; ++c) {
    f.w[static_cast<std::size_t>(c)] = ((c & 1) ? t[0] : 1 - t[0]) * (((c >> 1) & 1) ? t[1] : 1 - t[1]) * (((c >> 2) & 1) ? t[2] : 1 - t[2]);
  }
  return f;
}

// Grid fields in single precision: the solve is bound by memory traffic, and its
// tolerance (1e-3 by default) is far above float's resolution. Sums are in double.
using Field = std::vector<float>;

struct Level {
  Grid g;
  std::vector<Footprint> points;  // the points' footprints with their screening weights
  bool singular = false;          // unscreened: A has the constants as null space
  Field inverse_m;                // the smoother's 1 / M_kk
  std::array<std::size_t, 8> corner{};
  Field x, b, ax;                 // V-cycle workspace
};

double dot(const Field& a, const Field& b) {
  double s = 0;
  for (std::size_t i = 0; i < a.size(); ++i) s += static_cast<double>(a[i]) * b[i];
  return s;
}

// y = A x on one level.
void apply(const Level& lv, const Field& xv, Field& yv) {
  const Grid& g = lv.g;
  const std::size_t sx = 1, sy = static_cast<std::size_t>(g.n[0]), sz = sy * static_cast<std::size_t>(g.n[1]);
  const auto h = static_cast<float>(g.h);
  const float* __restrict x = xv.data();
  float* __restrict y = yv.data();
  // A node on the boundary has fewer neighbours (the free boundary's graph Laplacian).
  const auto edge_node = [&](int xx, int yy, int z, std::size_t i) {
    float s = 0;
    int d = 0;
    if (xx > 0) s += x[i - sx], ++d;
    if (xx + 1 < g.n[0]) s += x[i + sx], ++d;
    if (yy > 0) s += x[i - sy], ++d;
    if (yy + 1 < g.n[1]) s += x[i + sy], ++d;
    if (z > 0) s += x[i - sz], ++d;
    if (z + 1 < g.n[2]) s += x[i + sz], ++d;
    y[i] = h * (static_cast<float>(d) * x[i] - s);
  };
  for (int z = 0; z < g.n[2]; ++z) {
    for (int yy = 0; yy < g.n[1]; ++yy) {
      const std::size_t row = g.index(0, yy, z);
      if (yy == 0 || yy + 1 == g.n[1] || z == 0 || z + 1 == g.n[2]) {
        for (int xx = 0; xx < g.n[0]; ++xx) edge_node(xx, yy, z, row + static_cast<std::size_t>(xx));
        continue;
      }
      edge_node(0, yy, z, row);
      const std::size_t end = row + static_cast<std::size_t>(g.n[0]) - 1;
      for (std::size_t i = row + 1; i < end; ++i) {
        y[i] = h * (6 * x[i] - x[i - sx] - x[i + sx] - x[i - sy] - x[i + sy] - x[i - sz] - x[i + sz]);
      }
      edge_node(g.n[0] - 1, yy, z, end);
    }
  }
  for (const Footprint& f : lv.points) {
    double v = 0;
    for (std::size_t c = 0; c < 8; ++c) v += f.w[c] * x[f.base + lv.corner[c]];
    v *= f.weight;
    for (std::size_t c = 0; c < 8; ++c) y[f.base + lv.corner[c]] += static_cast<float>(f.w[c] * v);
  }
}

// The smoother's diagonal M: 7/6 of the Laplacian's diagonal plus the screening rows'
// absolute sums. Then A < 2M, so the damped Jacobi sweep x += M^-1 (b - A x)
// converges and the V-cycle is a symmetric positive definite preconditioner.
void build_smoother(Level& lv) {
  const Grid& g = lv.g;
  std::vector<double> m(g.size(), 0);
  for (int z = 0; z < g.n[2]; ++z) {
    for (int y = 0; y < g.n[1]; ++y) {
      for (int x = 0; x < g.n[0]; ++x) {
        const int d = (x > 0) + (x + 1 < g.n[0]) + (y > 0) + (y + 1 < g.n[1]) + (z > 0) + (z + 1 < g.n[2]);
        m[g.index(x, y, z)] = 7.0 / 6.0 * g.h * d;
      }
    }
  }
  for (const Footprint& f : lv.points) {
    for (std::size_t c = 0; c < 8; ++c) m[f.base + lv.corner[c]] += f.weight * f.w[c];
  }
  lv.inverse_m.resize(g.size());
  for (std::size_t i = 0; i < m.size(); ++i) lv.inverse_m[i] = static_cast<float>(1 / m[i]);
}

// fine += P coarse (trilinear; coarse node (i, j, k) is fine node (2i, 2j, 2k)).
void prolong_add(const Grid& coarse, const Field& xc, const Grid& fine, Field& xf) {
  std::size_t i = 0;
  for (int z = 0; z < fine.n[2]; ++z) {
    for (int y = 0; y < fine.n[1]; ++y) {
      for (int x = 0; x < fine.n[0]; ++x, ++i) {
        float v = 0;
        const float w = ((x & 1) ? 0.5f : 1.f) * ((y & 1) ? 0.5f : 1.f) * ((z & 1) ? 0.5f : 1.f);
        for (int c = 0; c < 8; ++c) {
          const int dx = c & 1, dy = (c >> 1) & 1, dz = (c >> 2) & 1;
          if ((dx && !(x & 1)) || (dy && !(y & 1)) || (dz && !(z & 1))) continue;
          v += w * xc[coarse.index(x / 2 + dx, y / 2 + dy, z / 2 + dz)];
        }
        xf[i] += v;
      }
    }
  }
}

// coarse = P^T fine.
void restrict_to(const Grid& fine, const Field& rf, const Grid& coarse, Field& rc) {
  std::fill(rc.begin(), rc.end(), 0.f);
  std::size_t i = 0;
  for (int z = 0; z < fine.n[2]; ++z) {
    for (int y = 0; y < fine.n[1]; ++y) {
      for (int x = 0; x < fine.n[0]; ++x, ++i) {
        const float w = ((x & 1) ? 0.5f : 1.f) * ((y & 1) ? 0.5f : 1.f) * ((z & 1) ? 0.5f : 1.f);
        for (int c = 0; c < 8; ++c) {
          const int dx = c & 1, dy = (c >> 1) & 1, dz = (c >> 2) & 1;
          if ((dx && !(x & 1)) || (dy && !(y & 1)) || (dz && !(z & 1))) continue;
          rc[coarse.index(x / 2 + dx, y / 2 + dy, z / 2 + dz)] += w * rf[i];
        }
      }
    }
  }
}

// Conjugate gradients preconditioned by the smoother's diagonal, from x = 0; solves
// the coarsest level (at most 32768 nodes) to round-off.
void coarse_solve(const Level& lv, const Field& b, Field& x) {
  const std::size_t n = b.size();
  std::vector<double> xd(n, 0), r(b.begin(), b.end()), z(n), p(n);
  // Unscreened, A is singular (constants): solve for the part of b it can reach, and
  // return the solution of zero mean, else round-off along the constants grows.
  const bool singular = lv.singular;
  const auto remove_mean = [&](std::vector<double>& v) {
    double mean = 0;
    for (const double e : v) mean += e;
    mean /= static_cast<double>(n);
    for (double& e : v) e -= mean;
  };
  if (singular) remove_mean(r);
  Field pf(n), q(n);
  for (std::size_t i = 0; i < n; ++i) z[i] = lv.inverse_m[i] * r[i];
  p = z;
  double rz = 0, rr = 0, bb = 0;
  for (std::size_t i = 0; i < n; ++i) rz += r[i] * z[i], rr += r[i] * r[i];
  bb = rr;
  for (std::size_t it = 0; it < 10 * n && rr > 1e-14 * bb; ++it) {
    for (std::size_t i = 0; i < n; ++i) pf[i] = static_cast<float>(p[i]);
    apply(lv, pf, q);
    double pq = 0;
    for (std::size_t i = 0; i < n; ++i) pq += p[i] * q[i];
    if (!(pq > 0)) break;
    const double a = rz / pq;
    double rz_next = 0;
    rr = 0;
    for (std::size_t i = 0; i < n; ++i) {
      xd[i] += a * p[i];
      r[i] -= a * q[i];
      z[i] = lv.inverse_m[i] * r[i];
      rz_next += r[i] * z[i];
      rr += r[i] * r[i];
    }
    for (std::size_t i = 0; i < n; ++i) p[i] = z[i] + rz_next / rz * p[i];
    rz = rz_next;
  }
  if (singular) remove_mean(xd);
  x.assign(xd.begin(), xd.end());
}

constexpr int kSweeps = 2;  // smoothing sweeps before and after each coarse correction

// levels[l].x = V(levels[l].b): one V-cycle from x = 0, symmetric (as many sweeps
// after the coarse correction as before), so it can precondition conjugate gradients.
void v_cycle(std::vector<Level>& levels, std::size_t l) {
  Level& lv = levels[l];
  if (l + 1 == levels.size()) {
    coarse_solve(lv, lv.b, lv.x);
    return;
  }
  Field &x = lv.x, &b = lv.b, &ax = lv.ax;
  const std::size_t n = b.size();
  for (std::size_t i = 0; i < n; ++i) x[i] = lv.inverse_m[i] * b[i];
  const auto sweep = [&] {
    apply(lv, x, ax);
    for (std::size_t i = 0; i < n; ++i) x[i] += lv.inverse_m[i] * (b[i] - ax[i]);
  };
  for (int s = 1; s < kSweeps; ++s) sweep();
  apply(lv, x, ax);
  for (std::size_t i = 0; i < n; ++i) ax[i] = b[i] - ax[i];
  Level& coarse = levels[l + 1];
  restrict_to(lv.g, ax, coarse.g, coarse.b);
  v_cycle(levels, l + 1);
  prolong_add(coarse.g, coarse.x, lv.g, x);
  for (int s = 0; s < kSweeps; ++s) sweep();
}

struct Solve {
  Field x;
  int iterations = 0;
  double residual = 0;  // relative to |b|
};

// Conjugate gradients on level l from the guess x, preconditioned by one V-cycle.
Solve conjugate_gradients(std::vector<Level>& levels, std::size_t l, const Field& b, Field x, double tolerance, int max_iterations) {
  Level& lv = levels[l];
  const std::size_t size = b.size();
  Solve out;
  Field r(size), dir(size), q(size);
  apply(lv, x, q);
  for (std::size_t i = 0; i < size; ++i) r[i] = b[i] - q[i];
  const double b_norm = std::sqrt(dot(b, b));
  out.residual = b_norm > 0 ? std::sqrt(dot(r, r)) / b_norm : 0;
  if (out.residual > tolerance) {
    lv.b = r;
    v_cycle(levels, l);
    dir = lv.x;
    double rz = dot(r, lv.x);
    while (out.iterations < max_iterations) {
      ++out.iterations;
      apply(lv, dir, q);
      const auto a = static_cast<float>(rz / dot(dir, q));
      for (std::size_t i = 0; i < size; ++i) x[i] += a * dir[i], r[i] -= a * q[i];
      out.residual = std::sqrt(dot(r, r)) / b_norm;
      if (out.residual <= tolerance) break;
      lv.b = r;
      v_cycle(levels, l);
      const double rz_next = dot(r, lv.x);
      const auto beta = static_cast<float>(rz_next / rz);
      for (std::size_t i = 0; i < size; ++i) dir[i] = lv.x[i] + beta * dir[i];
      rz = rz_next;
    }
  }
  out.x = std::move(x);
  return out;
}

}  // namespace

ScreenedPoissonMesh screened_poisson_mesh(const PointCloud& points, const PointCloud& normals, const std::vector<double>& areas,
                                          const ScreenedPoissonParams& p) {
  const char* who = "screened_poisson";
  require_points(points, 4, who);
  if (normals.rows() != points.rows() || areas.size() != static_cast<std::size_t>(points.rows())) {
    throw InputError(std::string(who) + ": " + std::to_string(points.rows()) + " points, " + std::to_string(normals.rows()) +
                     " normals and " + std::to_string(areas.size()) + " areas; give one of each per point");
  }
  if (!normals.allFinite()) throw InputError(std::string(who) + ": a normal is not finite");
  for (const double a : areas) {
    if (!(a > 0 && std::isfinite(a))) throw InputError(std::string(who) + ": every area must be positive and finite");
  }
  check_range(p.step, 2e-4, 0.05, who, "step", " m");
  check_range(p.screening, 0, 1e4, who, "screening");
  check_range(p.tolerance, 1e-6, 0.1, who, "tolerance");
  check_range(p.max_iterations, 1, 1000, who, "max_iterations");

  // Grid: the bounding box plus four steps, rounded up to whole coarsest cells. The
  // coarsest level keeps at least 3 nodes on the shortest axis and at most 32768 in all.
  const Vec3 lo = points.colwise().minCoeff().transpose(), hi = points.colwise().maxCoeff().transpose();
  const Vec3 extent = (hi - lo).array() + 8 * p.step;
  const auto too_many = [&](double nodes) {
    return InputError(std::string(who) + ": step = " + std::to_string(p.step) + " m gives " + std::to_string(nodes) +
                      " grid nodes on this cloud, more than 5e7; raise step");
  };
  const double at_least = (extent / p.step).array().ceil().prod();
  if (!(at_least <= 5e7)) throw too_many(at_least);  // before any count meets an int
  int halvings = 0;
  const auto cells_at = [&](int k) {
    std::array<int, 3> m{};
    const double coarse = p.step * std::ldexp(1.0, k);
    for (int a = 0; a < 3; ++a) m[static_cast<std::size_t>(a)] = std::max(2, static_cast<int>(std::ceil(extent(a) / coarse)));
    return m;
  };
  while (halvings < 12) {
    const auto m = cells_at(halvings);
    if (static_cast<double>(m[0] + 1) * (m[1] + 1) * (m[2] + 1) <= 32768 || *std::min_element(m.begin(), m.end()) <= 2) break;
    ++halvings;
  }
  const std::array<int, 3> m = cells_at(halvings);
  std::array<int, 3> n{};
  for (int a = 0; a < 3; ++a) n[static_cast<std::size_t>(a)] = m[static_cast<std::size_t>(a)] * (1 << halvings) + 1;
  const double nodes = static_cast<double>(n[0]) * n[1] * n[2];
  if (nodes > 5e7) throw too_many(nodes);
  Grid finest;
  finest.n = n;
  finest.h = p.step;
  finest.origin = 0.5 * (lo + hi) - 0.5 * p.step * Vec3(n[0] - 1, n[1] - 1, n[2] - 1);

  std::vector<Level> levels(static_cast<std::size_t>(halvings) + 1);
  const double w = p.screening / p.step;
  for (std::size_t l = 0; l < levels.size(); ++l) {
    Level& lv = levels[l];
    if (l == 0) {
      lv.g = finest;
    } else {
      const Grid& f = levels[l - 1].g;
      lv.g = f;
      lv.g.h = 2 * f.h;
      for (int a = 0; a < 3; ++a) lv.g.n[static_cast<std::size_t>(a)] = (f.n[static_cast<std::size_t>(a)] - 1) / 2 + 1;
    }
    for (int c = 0; c < 8; ++c) lv.corner[static_cast<std::size_t>(c)] = lv.g.corner(c);
    // Built also when w = 0 (weights 0): the finest level's serve the iso-value.
    const std::array<int, 3> cells{lv.g.n[0] - 1, lv.g.n[1] - 1, lv.g.n[2] - 1};
    lv.points.reserve(areas.size());
    for (Eigen::Index i = 0; i < points.rows(); ++i) {
      Footprint f = footprint(lv.g, points.row(i).transpose(), Vec3::Zero(), cells);
      f.weight = w * areas[static_cast<std::size_t>(i)];
      lv.points.push_back(f);
    }
    lv.singular = !(w > 0);
    build_smoother(lv);
    lv.x.resize(lv.g.size());
    lv.b.resize(lv.g.size());
    lv.ax.resize(lv.g.size());
  }

  // b: the splatted normals' divergence. Edges along axis a join node j to j + e_a;
  // their midpoints form a lattice shifted half a step along a.
  std::vector<double> divergence(finest.size(), 0);
  for (int a = 0; a < 3; ++a) {
    std::array<int, 3> cells{n[0] - 1, n[1] - 1, n[2] - 1};
    --cells[static_cast<std::size_t>(a)];
    Vec3 shift = Vec3::Zero();
    shift(a) = 0.5;
    const std::size_t along = finest.corner(1 << a);
    for (Eigen::Index i = 0; i < points.rows(); ++i) {
      const Footprint f = footprint(finest, points.row(i).transpose(), shift, cells);
      const double s = areas[static_cast<std::size_t>(i)] * normals(i, a) / finest.h;
      for (std::size_t c = 0; c < 8; ++c) {
        const std::size_t tail = f.base + levels[0].corner[c];
        divergence[tail] -= s * f.w[c];
        divergence[tail + along] += s * f.w[c];
      }
    }
  }

  ScreenedPoissonMesh out;
  out.grid = n;
  out.levels = static_cast<int>(levels.size());
  const Field rhs(divergence.begin(), divergence.end());
  divergence = std::vector<double>();
  const Solve solved = conjugate_gradients(levels, 0, rhs, Field(rhs.size(), 0), p.tolerance, p.max_iterations);
  const Field& x = solved.x;
  out.iterations = solved.iterations;
  out.residual = solved.residual;
  const std::size_t size = finest.size();

  // Contour at the points' mean value (Kazhdan & Hoppe 2013 Sec. 4.1: the iso-value is
  // the area-weighted average of chi at the samples).
  double sum = 0, weight = 0;
  for (std::size_t i = 0; i < areas.size(); ++i) {
    const Footprint& f = levels[0].points[i];
    double v = 0;
    for (std::size_t c = 0; c < 8; ++c) v += f.w[c] * x[f.base + levels[0].corner[c]];
    sum += areas[i] * v;
    weight += areas[i];
  }
  out.iso = sum / weight;
  std::vector<double> values(size);
  for (std::size_t i = 0; i < size; ++i) values[i] = x[i] - out.iso;
  contour_grid(values, n, finest.origin, finest.h, out.vertices, out.triangles);
  return out;
}

}  // namespace grapebench
