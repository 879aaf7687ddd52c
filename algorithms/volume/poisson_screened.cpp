#include "algorithms/volume/poisson_screened.h"
#include "synth/run_stop.h"

#include "algorithms/volume/grid_contour.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
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

// A point's screening term on one level, in the form the solve applies it: the
// interpolation weights w and the same scaled by the point's weight (w * a_i).
struct ScreenedPoint {
  std::size_t base = 0;
  std::array<float, 8> w{}, weighted{};
  std::array<std::uint32_t, 8> slot{};  // the corners' places in Level::screened_nodes
};

// The screening of all the points in one grid cell, summed: the symmetric 8 x 8 matrix
// sum_i (w a_i) w_i w_i^T on the cell's corners. Cheaper than the points themselves on
// coarse levels, where many share a cell.
struct ScreenedCell {
  std::size_t base = 0;
  std::array<float, 64> m{};  // row-major, corner by corner
  std::array<std::uint32_t, 8> slot{};
};

// Grid fields in single precision: the solve is bound by memory traffic, and its
// tolerance (1e-3 by default) is far above float's resolution. Sums are in double.
using Field = std::vector<float>;

struct Level {
  Grid g;
  // The screening term, per point or per cell (one of the two is empty), by base.
  std::vector<ScreenedPoint> points;
  std::vector<ScreenedCell> cells;
  std::vector<std::size_t> screened_nodes;  // the nodes the points touch, ascending
  Field screening;                          // per screened node: the screening part of A x
  bool singular = false;          // unscreened: A has the constants as null space
  Field inverse_m;                // the smoother's 1 / M_kk
  std::array<std::size_t, 8> corner{};
  Field x, b, ax, x_next;         // V-cycle workspace
};

// Sum of a_i b_i in double, in eight interleaved partial sums: a fixed order (the
// same bits on every run) that the compiler can vectorise.
double dot(const Field& a, const Field& b) {
  std::array<double, 8> lane{};
  const std::size_t n = a.size(), whole = n - n % 8;
  for (std::size_t i = 0; i < whole; i += 8) {
    for (std::size_t k = 0; k < 8; ++k) lane[k] += static_cast<double>(a[i + k]) * b[i + k];
  }
  double s = 0;
  for (std::size_t i = whole; i < n; ++i) s += static_cast<double>(a[i]) * b[i];
  for (const double l : lane) s += l;
  return s;
}

// Calls row(first, ax) for every grid row (x fastest): ax holds (A x) at nodes first,
// first + 1, ..., one row's worth. A is the grid Laplacian (h L) plus the points'
// screening, which is gathered first into lv.screening (a few nodes per point) and
// merged in row by row, so each caller consumes A x in the pass that computes it.
template <class Row>
void apply_rows(Level& lv, const Field& xv, Row&& row) {
  const float* __restrict x = xv.data();
  std::fill(lv.screening.begin(), lv.screening.end(), 0.f);
  for (const ScreenedPoint& f : lv.points) {
    float v = 0;
    for (std::size_t c = 0; c < 8; ++c) v += f.w[c] * x[f.base + lv.corner[c]];
    for (std::size_t c = 0; c < 8; ++c) lv.screening[f.slot[c]] += f.weighted[c] * v;
  }
  for (const ScreenedCell& cell : lv.cells) {
    std::array<float, 8> xc{};
    for (std::size_t d = 0; d < 8; ++d) xc[d] = x[cell.base + lv.corner[d]];
    for (std::size_t c = 0; c < 8; ++c) {
      float v = 0;
      for (std::size_t d = 0; d < 8; ++d) v += cell.m[8 * c + d] * xc[d];
      lv.screening[cell.slot[c]] += v;
    }
  }
  const Grid& g = lv.g;
  const std::size_t sx = 1, sy = static_cast<std::size_t>(g.n[0]), sz = sy * static_cast<std::size_t>(g.n[1]);
  const auto h = static_cast<float>(g.h);
  std::vector<float> buffer(sy);
  float* __restrict ax = buffer.data();
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
    ax[xx] = h * (static_cast<float>(d) * x[i] - s);
  };
  std::size_t next = 0;  // the first screened node not yet merged
  for (int z = 0; z < g.n[2]; ++z) {
    for (int yy = 0; yy < g.n[1]; ++yy) {
      const std::size_t first = g.index(0, yy, z);
      if (yy == 0 || yy + 1 == g.n[1] || z == 0 || z + 1 == g.n[2]) {
        for (int xx = 0; xx < g.n[0]; ++xx) edge_node(xx, yy, z, first + static_cast<std::size_t>(xx));
      } else {
        edge_node(0, yy, z, first);
        // Signed strides: the neighbours below lie before `c` (unsigned offsets would
        // wrap the pointer, which UBSan flags).
        const auto dx = static_cast<std::ptrdiff_t>(sx), dy = static_cast<std::ptrdiff_t>(sy),
                   dz = static_cast<std::ptrdiff_t>(sz);
        const float* __restrict c = x + first;
        for (std::ptrdiff_t i = 1; i + 1 < dy; ++i) {
          ax[i] = h * (6 * c[i] - c[i - dx] - c[i + dx] - c[i - dy] - c[i + dy] - c[i - dz] - c[i + dz]);
        }
        edge_node(g.n[0] - 1, yy, z, first + sy - 1);
      }
      for (; next < lv.screened_nodes.size() && lv.screened_nodes[next] < first + sy; ++next) {
        ax[lv.screened_nodes[next] - first] += lv.screening[next];
      }
      row(first, static_cast<const float*>(ax));
    }
  }
}

// y = A x on one level.
void apply(Level& lv, const Field& x, Field& y) {
  apply_rows(lv, x, [&](std::size_t first, const float* ax) { std::copy(ax, ax + lv.g.n[0], y.data() + first); });
}

// The points' screening on one level (weight w * area each): per point, or per cell
// where there are over four points to a cell on average.
void build_screening(Level& lv, const PointCloud& points, const std::vector<double>& areas, double w) {
  const std::array<int, 3> cells{lv.g.n[0] - 1, lv.g.n[1] - 1, lv.g.n[2] - 1};
  struct Weighted {
    Footprint f;
    double weight;
  };
  std::vector<Weighted> all;
  all.reserve(areas.size());
  for (Eigen::Index i = 0; i < points.rows(); ++i) {
    all.push_back({footprint(lv.g, points.row(i).transpose(), Vec3::Zero(), cells), w * areas[static_cast<std::size_t>(i)]});
  }
  std::stable_sort(all.begin(), all.end(), [](const Weighted& a, const Weighted& b) { return a.f.base < b.f.base; });
  for (const Weighted& p : all) {
    for (std::size_t c = 0; c < 8; ++c) lv.screened_nodes.push_back(p.f.base + lv.corner[c]);
  }
  std::sort(lv.screened_nodes.begin(), lv.screened_nodes.end());
  lv.screened_nodes.erase(std::unique(lv.screened_nodes.begin(), lv.screened_nodes.end()), lv.screened_nodes.end());
  lv.screening.resize(lv.screened_nodes.size());
  const auto slots = [&](std::size_t base) {
    std::array<std::uint32_t, 8> slot{};
    for (std::size_t c = 0; c < 8; ++c) {
      const auto at = std::lower_bound(lv.screened_nodes.begin(), lv.screened_nodes.end(), base + lv.corner[c]);
      slot[c] = static_cast<std::uint32_t>(at - lv.screened_nodes.begin());
    }
    return slot;
  };
  std::size_t occupied = 0;
  for (std::size_t i = 0; i < all.size(); ++i) occupied += i == 0 || all[i].f.base != all[i - 1].f.base;
  if (4 * occupied < all.size()) {
    for (std::size_t i = 0; i < all.size();) {
      std::array<double, 64> m{};
      const std::size_t base = all[i].f.base;
      for (; i < all.size() && all[i].f.base == base; ++i) {
        const Footprint& f = all[i].f;
        for (std::size_t c = 0; c < 8; ++c) {
          for (std::size_t d = 0; d < 8; ++d) m[8 * c + d] += all[i].weight * f.w[c] * f.w[d];
        }
      }
      ScreenedCell cell;
      cell.base = base;
      for (std::size_t k = 0; k < 64; ++k) cell.m[k] = static_cast<float>(m[k]);
      cell.slot = slots(base);
      lv.cells.push_back(cell);
    }
    return;
  }
  lv.points.reserve(all.size());
  for (const Weighted& p : all) {
    ScreenedPoint sp;
    sp.base = p.f.base;
    for (std::size_t c = 0; c < 8; ++c) {
      sp.w[c] = static_cast<float>(p.f.w[c]);
      sp.weighted[c] = static_cast<float>(p.weight * p.f.w[c]);
    }
    sp.slot = slots(sp.base);
    lv.points.push_back(sp);
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
  for (const ScreenedPoint& f : lv.points) {
    for (std::size_t c = 0; c < 8; ++c) m[f.base + lv.corner[c]] += f.weighted[c];
  }
  for (const ScreenedCell& cell : lv.cells) {
    for (std::size_t c = 0; c < 8; ++c) {
      for (std::size_t d = 0; d < 8; ++d) m[cell.base + lv.corner[c]] += cell.m[8 * c + d];
    }
  }
  lv.inverse_m.resize(g.size());
  for (std::size_t i = 0; i < m.size(); ++i) lv.inverse_m[i] = static_cast<float>(1 / m[i]);
}

// Calls visit(fine_row, parent_rows, parents, w) for every fine row (y, z), x fastest:
// the first `parents` entries of parent_rows start the coarse rows it interpolates from
// in y and z (coarse node (i, j, k) is fine node (2i, 2j, 2k); an odd fine index is half
// of each coarse neighbour), each with weight w.
template <class Visit>
void each_fine_row(const Grid& fine, const Grid& coarse, Visit&& visit) {
  for (int z = 0; z < fine.n[2]; ++z) {
    for (int y = 0; y < fine.n[1]; ++y) {
      const bool odd_z = (z & 1) != 0, odd_y = (y & 1) != 0;
      std::array<std::size_t, 4> rows{};
      int parents = 0;
      for (int dz = 0; dz <= (odd_z ? 1 : 0); ++dz) {
        for (int dy = 0; dy <= (odd_y ? 1 : 0); ++dy) rows[static_cast<std::size_t>(parents++)] = coarse.index(0, y / 2 + dy, z / 2 + dz);
      }
      visit(fine.index(0, y, z), rows, parents, (odd_z ? 0.5f : 1.f) * (odd_y ? 0.5f : 1.f));
    }
  }
}

// fine += P coarse (trilinear), row by row: the y and z weights combine up to four
// coarse rows, then x interpolates.
void prolong_add(const Grid& coarse, const Field& xc, const Grid& fine, Field& xf) {
  const auto nc = static_cast<std::size_t>(coarse.n[0]);
  std::vector<float> row(nc);
  each_fine_row(fine, coarse, [&](std::size_t first, const std::array<std::size_t, 4>& rows, int parents, float w) {
    std::fill(row.begin(), row.end(), 0.f);
    for (int k = 0; k < parents; ++k) {
      const float* c = xc.data() + rows[static_cast<std::size_t>(k)];
      for (std::size_t i = 0; i < nc; ++i) row[i] += w * c[i];
    }
    float* f = xf.data() + first;
    for (std::size_t i = 0; i + 1 < nc; ++i) {
      f[2 * i] += row[i];
      f[2 * i + 1] += 0.5f * (row[i] + row[i + 1]);
    }
    f[2 * (nc - 1)] += row[nc - 1];
  });
}

// coarse = P^T fine: each fine row restricted along x, then added to the up to four
// coarse rows it interpolates from.
void restrict_to(const Grid& fine, const Field& rf, const Grid& coarse, Field& rc) {
  std::fill(rc.begin(), rc.end(), 0.f);
  const auto nc = static_cast<std::size_t>(coarse.n[0]);
  std::vector<float> row(nc);
  each_fine_row(fine, coarse, [&](std::size_t first, const std::array<std::size_t, 4>& rows, int parents, float w) {
    const float* f = rf.data() + first;
    row[0] = f[0] + 0.5f * f[1];
    for (std::size_t i = 1; i + 1 < nc; ++i) row[i] = f[2 * i] + 0.5f * (f[2 * i - 1] + f[2 * i + 1]);
    row[nc - 1] = f[2 * (nc - 1)] + 0.5f * f[2 * (nc - 1) - 1];
    for (int k = 0; k < parents; ++k) {
      float* c = rc.data() + rows[static_cast<std::size_t>(k)];
      for (std::size_t i = 0; i < nc; ++i) c[i] += w * row[i];
    }
  });
}

// Conjugate gradients preconditioned by the smoother's diagonal, from x = 0; solves
// the coarsest level (at most 32768 nodes) to round-off.
void coarse_solve(Level& lv, const Field& b, Field& x) {
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

// levels[l].x = V(b): one V-cycle from x = 0, symmetric (as many sweeps after the
// coarse correction as before), so it can precondition conjugate gradients. The
// coarser levels take their right-hand side in their own b.
void v_cycle(std::vector<Level>& levels, std::size_t l, const Field& b) {
  Level& lv = levels[l];
  if (l + 1 == levels.size()) {
    coarse_solve(lv, b, lv.x);
    return;
  }
  const std::size_t n = b.size(), row = static_cast<std::size_t>(lv.g.n[0]);
  for (std::size_t i = 0; i < n; ++i) lv.x[i] = lv.inverse_m[i] * b[i];
  // One damped Jacobi sweep x += M^-1 (b - A x), into x_next in the pass that computes A x.
  const auto sweep = [&] {
    const float* __restrict x = lv.x.data();
    const float* __restrict m = lv.inverse_m.data();
    float* __restrict out = lv.x_next.data();
    apply_rows(lv, lv.x, [&](std::size_t first, const float* __restrict ax) {
      for (std::size_t i = 0; i < row; ++i) out[first + i] = x[first + i] + m[first + i] * (b[first + i] - ax[i]);
    });
    lv.x.swap(lv.x_next);
  };
  for (int s = 1; s < kSweeps; ++s) sweep();
  float* __restrict residual = lv.ax.data();
  apply_rows(lv, lv.x, [&](std::size_t first, const float* __restrict ax) {
    for (std::size_t i = 0; i < row; ++i) residual[first + i] = b[first + i] - ax[i];
  });
  Level& coarse = levels[l + 1];
  restrict_to(lv.g, lv.ax, coarse.g, coarse.b);
  v_cycle(levels, l + 1, coarse.b);
  prolong_add(coarse.g, coarse.x, lv.g, lv.x);
  for (int s = 0; s < kSweeps; ++s) sweep();
}

struct Solve {
  Field x;
  int iterations = 0;
  double residual = 0;  // relative to |b|
};

// Conjugate gradients on the finest level from x = 0, preconditioned by one V-cycle.
// b is taken over as the residual.
Solve conjugate_gradients(std::vector<Level>& levels, Field b, double tolerance, int max_iterations) {
  Level& lv = levels[0];
  const std::size_t size = b.size();
  Solve out;
  out.x.assign(size, 0.f);
  Field& x = out.x;
  Field r = std::move(b), dir(size), q(size);
  const double b_norm = std::sqrt(dot(r, r));
  out.residual = b_norm > 0 ? 1 : 0;
  if (out.residual <= tolerance) return out;
  v_cycle(levels, 0, r);
  dir = lv.x;
  double rz = dot(r, lv.x);
  while (out.iterations < max_iterations) {
    throw_if_stop_requested();  // a run over its time budget (synth/run_stop.h)
    ++out.iterations;
    apply(lv, dir, q);
    const auto a = static_cast<float>(rz / dot(dir, q));
    for (std::size_t i = 0; i < size; ++i) x[i] += a * dir[i], r[i] -= a * q[i];
    out.residual = std::sqrt(dot(r, r)) / b_norm;
    if (out.residual <= tolerance) break;
    v_cycle(levels, 0, r);
    const double rz_next = dot(r, lv.x);
    const auto beta = static_cast<float>(rz_next / rz);
    for (std::size_t i = 0; i < size; ++i) dir[i] = lv.x[i] + beta * dir[i];
    rz = rz_next;
  }
  return out;
}

// The field between the nodes for the mesh's vertices: Catmull-Rom (Keys 1981 cubic
// convolution, a = -1/2) along each axis, which interpolates the nodes and is exact on
// quadratics. Trilinear interpolation, which the contour's edge crossings follow, has
// an O(h^2 / R) error on a surface of curvature 1/R; this one O(h^3).
struct CubicField {
  const Field& v;
  const Grid& g;
  // Value at p (m) and its gradient (per m). Within a node of the grid's edge the
  // stencil stays inside and the cubic extrapolates.
  double at(const Vec3& p, Vec3& gradient) const {
    std::array<std::array<double, 4>, 3> w{}, dw{};
    std::size_t first = 0;
    const std::array<std::size_t, 3> stride{1, static_cast<std::size_t>(g.n[0]),
                                            static_cast<std::size_t>(g.n[0]) * static_cast<std::size_t>(g.n[1])};
    for (std::size_t a = 0; a < 3; ++a) {
      const double u = (p(static_cast<Eigen::Index>(a)) - g.origin(static_cast<Eigen::Index>(a))) / g.h;
      const int i = std::clamp(static_cast<int>(std::floor(u)), 1, g.n[a] - 3);
      const double t = std::clamp(u - i, -1.0, 2.0), t2 = t * t, t3 = t2 * t;
      w[a] = {(-t3 + 2 * t2 - t) / 2, (3 * t3 - 5 * t2 + 2) / 2, (-3 * t3 + 4 * t2 + t) / 2, (t3 - t2) / 2};
      dw[a] = {(-3 * t2 + 4 * t - 1) / 2, (9 * t2 - 10 * t) / 2, (-9 * t2 + 8 * t + 1) / 2, (3 * t2 - 2 * t) / 2};
      first += static_cast<std::size_t>(i - 1) * stride[a];
    }
    double value = 0, gx = 0, gy = 0, gz = 0;
    for (std::size_t k = 0; k < 4; ++k) {
      double vz = 0, xz = 0, yz = 0;
      for (std::size_t j = 0; j < 4; ++j) {
        const float* row = v.data() + first + k * stride[2] + j * stride[1];
        double vx = 0, dx = 0;
        for (std::size_t i = 0; i < 4; ++i) vx += w[0][i] * row[i], dx += dw[0][i] * row[i];
        vz += w[1][j] * vx, yz += dw[1][j] * vx, xz += w[1][j] * dx;
      }
      value += w[2][k] * vz, gx += w[2][k] * xz, gy += w[2][k] * yz, gz += dw[2][k] * vz;
    }
    gradient = Vec3(gx, gy, gz) / g.h;
    return value;
  }
};

// Moves p onto the zero level of `field` by Newton steps along the gradient, and gives
// the unit gradient there (the outward normal). Keeps p where that would take it more
// than one step h away (a flat or kinked field).
Vec3 onto_level_set(const CubicField& field, const Vec3& p, Vec3& normal) {
  Vec3 q = p, gradient;
  normal = Vec3::Zero();
  for (int k = 0; k < 8; ++k) {
    const double f = field.at(q, gradient), g2 = gradient.squaredNorm();
    if (!(g2 > 0)) break;
    normal = gradient / std::sqrt(g2);  // at the last point but one: the move after is far below h
    const Vec3 move = (f / g2) * gradient;
    if ((q - move - p).squaredNorm() > field.g.h * field.g.h) break;
    q -= move;
    // Newton converges quadratically: after a move of 1e-3 h the next would be ~1e-6 h.
    if (move.squaredNorm() < 1e-6 * field.g.h * field.g.h) return q;
  }
  return p;
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
    lv.singular = !(w > 0);
    if (!lv.singular) build_screening(lv, points, areas, w);
    build_smoother(lv);
    lv.x.resize(lv.g.size());
    lv.x_next.resize(lv.g.size());
    if (l > 0) lv.b.resize(lv.g.size());  // the finest level's is the solve's residual
    lv.ax.resize(lv.g.size());
  }

  // b: the splatted normals' divergence. Edges along axis a join node j to j + e_a;
  // their midpoints form a lattice shifted half a step along a.
  Field divergence(finest.size(), 0.f);
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
        divergence[tail] -= static_cast<float>(s * f.w[c]);
        divergence[tail + along] += static_cast<float>(s * f.w[c]);
      }
    }
  }

  ScreenedPoissonMesh out;
  out.grid = n;
  out.levels = static_cast<int>(levels.size());
  Solve solved = conjugate_gradients(levels, std::move(divergence), p.tolerance, p.max_iterations);
  Field& x = solved.x;
  out.iterations = solved.iterations;
  out.residual = solved.residual;
  const std::size_t size = finest.size();

  // Contour at the points' mean value (Kazhdan & Hoppe 2013 Sec. 4.1: the iso-value is
  // the area-weighted average of chi at the samples), read from the same cubic
  // interpolant that places the vertices: the trilinear one reads ~h^2 / 8R too high
  // where the surface curves, which puts a berry's surface outside its points.
  const CubicField field{x, finest};  // reads x as it is when asked: below, less the iso-value
  double sum = 0, weight = 0;
  for (Eigen::Index i = 0; i < points.rows(); ++i) {
    Vec3 unused;
    sum += areas[static_cast<std::size_t>(i)] * field.at(points.row(i).transpose(), unused);
    weight += areas[static_cast<std::size_t>(i)];
  }
  out.iso = sum / weight;
  const auto iso = static_cast<float>(out.iso);
  for (std::size_t i = 0; i < size; ++i) x[i] -= iso;
  // Where the points leave the surface open (a stalk's cut end, a side no camera saw),
  // the inside can run out to the grid's boundary. Those boundary nodes are set just
  // outside, so the mesh is capped there and closed.
  const auto cap = [&](std::size_t i) {
    if (x[i] < 0) x[i] = std::numeric_limits<float>::min(), ++out.capped;
  };
  for (int z = 0; z < n[2]; ++z) {
    for (int y = 0; y < n[1]; ++y) {
      const bool face = z == 0 || y == 0 || z + 1 == n[2] || y + 1 == n[1];
      for (int xx = 0; xx < n[0]; xx += face ? 1 : n[0] - 1) cap(finest.index(xx, y, z));
    }
  }
  contour_grid(x, n, finest.origin, finest.h, out.vertices, out.triangles);
  // The contour's vertices sit on the trilinear interpolant's level, which misses the
  // smooth field's by O(h^2 / R); they are moved onto the cubic one's.
  out.normals.resize(out.vertices.size());
  for (std::size_t i = 0; i < out.vertices.size(); ++i) out.vertices[i] = onto_level_set(field, out.vertices[i], out.normals[i]);
  return out;
}

}  // namespace grapebench
