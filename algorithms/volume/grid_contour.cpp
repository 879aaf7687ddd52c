#include "algorithms/volume/grid_contour.h"

#include <algorithm>
#include <cstdint>

namespace grapebench {

namespace {

// Marching tetrahedra over the grid values (negative inside), each cube split into
// the six tetrahedra of Kuhn's decomposition, which neighbouring cubes share faces
// with, so the surface closes. Surface vertices sit on grid edges and are shared
// through the edge's node pair, so the mesh is indexed and closed.
template <class Value>
class Contour {
 public:
  Contour(const std::vector<Value>& f, const std::array<int, 3>& n, const Vec3& origin, double step, std::vector<Vec3>& vertices,
          std::vector<std::array<int, 3>>& triangles)
      : f_(f), n_(n), origin_(origin), step_(step), vertices_(vertices), triangles_(triangles) {}

  void run() {
    // Kuhn: the six monotone paths from corner (0,0,0) to (1,1,1).
    static constexpr int kAxisOrders[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
    const std::size_t per_layer = static_cast<std::size_t>(n_[0]) * static_cast<std::size_t>(n_[1]) * 7;
    layers_[0].assign(per_layer, -1);
    for (int z = 0; z + 1 < n_[2]; ++z) {
      layers_[static_cast<std::size_t>((z + 1) & 1)].assign(per_layer, -1);  // layer z + 1 starts empty
      for (int y = 0; y + 1 < n_[1]; ++y) {
        for (int x = 0; x + 1 < n_[0]; ++x) {
          if (uniform_cube({x, y, z})) continue;  // most of the grid: no surface
          for (const auto& order : kAxisOrders) {
            std::array<int, 3> c{x, y, z};
            std::array<std::int64_t, 4> tet{};
            tet[0] = node(c);
            for (int k = 0; k < 3; ++k) {
              ++c[static_cast<std::size_t>(order[k])];
              tet[static_cast<std::size_t>(k + 1)] = node(c);
            }
            tetrahedron(tet);
          }
        }
      }
    }
  }

 private:
  std::int64_t node(const std::array<int, 3>& c) const {
    return (static_cast<std::int64_t>(c[2]) * n_[1] + c[1]) * n_[0] + c[0];
  }
  Vec3 position(std::int64_t id) const {
    const std::int64_t x = id % n_[0], y = (id / n_[0]) % n_[1], z = id / (static_cast<std::int64_t>(n_[0]) * n_[1]);
    return origin_ + step_ * Vec3(static_cast<double>(x), static_cast<double>(y), static_cast<double>(z));
  }
  bool inside(std::int64_t id) const { return f_[static_cast<std::size_t>(id)] < 0; }
  // True when the cube's eight corners lie on the same side, so none of its
  // tetrahedra is cut.
  bool uniform_cube(const std::array<int, 3>& c) const {
    const bool first = inside(node(c));
    for (int corner = 1; corner < 8; ++corner) {
      const std::array<int, 3> q{c[0] + (corner & 1), c[1] + ((corner >> 1) & 1), c[2] + ((corner >> 2) & 1)};
      if (inside(node(q)) != first) return false;
    }
    return true;
  }

  // The surface vertex on the edge (a inside, b outside), linearly interpolated. Every
  // Kuhn edge runs from a node to one of its seven successors (+x, +y, +z and their
  // sums), so a vertex is known by its lower node and that step; only the lower
  // nodes of two z-layers are live at a time.
  int edge_vertex(std::int64_t a, std::int64_t b) {
    const std::int64_t lo = std::min(a, b), hi = std::max(a, b);
    const std::int64_t row = n_[0], layer = static_cast<std::int64_t>(n_[0]) * n_[1];
    const std::int64_t d = hi - lo, z = lo / layer;
    const int step = (d >= layer ? 4 : 0) + ((d % layer) >= row ? 2 : 0) + (d % row != 0 ? 1 : 0);
    int& id = layers_[static_cast<std::size_t>(z & 1)][static_cast<std::size_t>(lo - z * layer) * 7 + static_cast<std::size_t>(step - 1)];
    if (id < 0) {
      id = static_cast<int>(vertices_.size());
      const double fa = static_cast<double>(f_[static_cast<std::size_t>(a)]), fb = static_cast<double>(f_[static_cast<std::size_t>(b)]);
      const double t = fa / (fa - fb);  // fa < 0 <= fb
      vertices_.push_back(position(a) + t * (position(b) - position(a)));
    }
    return id;
  }

  // A surface vertex and the midpoint of its grid edge. Orientation is decided on the
  // midpoints: the interpolated vertices can coincide (a node valued exactly 0 is
  // reached by several edges), the midpoints never do, and a cut triangle faces the
  // same way wherever along its edges its corners sit.
  struct Cut {
    int id;
    Vec3 mid;
  };
  Cut cut(std::int64_t in, std::int64_t out) { return {edge_vertex(in, out), 0.5 * (position(in) + position(out))}; }

  // A triangle facing from the inside nodes to the outside ones.
  void triangle(const Cut& i, const Cut& j, const Cut& k, const Vec3& towards_outside) {
    if ((j.mid - i.mid).cross(k.mid - i.mid).dot(towards_outside) >= 0) {
      triangles_.push_back({i.id, j.id, k.id});
    } else {
      triangles_.push_back({i.id, k.id, j.id});
    }
  }

  void tetrahedron(const std::array<std::int64_t, 4>& t) {
    std::array<std::int64_t, 4> in{}, outside{};
    int n_in = 0, n_out = 0;
    for (const auto v : t) (inside(v) ? in[static_cast<std::size_t>(n_in++)] : outside[static_cast<std::size_t>(n_out++)]) = v;
    if (n_in == 0 || n_out == 0) return;
    Vec3 ci = Vec3::Zero(), co = Vec3::Zero();
    for (int k = 0; k < n_in; ++k) ci += position(in[static_cast<std::size_t>(k)]) / n_in;
    for (int k = 0; k < n_out; ++k) co += position(outside[static_cast<std::size_t>(k)]) / n_out;
    const Vec3 dir = co - ci;
    if (n_in == 1 || n_out == 1) {
      // One node alone on its side: the triangle cuts its three edges.
      const bool lone_inside = n_in == 1;
      const std::int64_t lone = lone_inside ? in[0] : outside[0];
      std::array<Cut, 3> v{};
      for (int k = 0; k < 3; ++k) {
        const std::int64_t other = lone_inside ? outside[static_cast<std::size_t>(k)] : in[static_cast<std::size_t>(k)];
        v[static_cast<std::size_t>(k)] = lone_inside ? cut(lone, other) : cut(other, lone);
      }
      triangle(v[0], v[1], v[2], dir);
      return;
    }
    // Two and two: a quad through the four crossing edges, in cyclic order.
    const Cut a = cut(in[0], outside[0]), b = cut(in[0], outside[1]);
    const Cut c = cut(in[1], outside[1]), d = cut(in[1], outside[0]);
    triangle(a, b, c, dir);
    triangle(a, c, d, dir);
  }

  const std::vector<Value>& f_;
  std::array<int, 3> n_;
  Vec3 origin_;
  double step_;
  std::vector<Vec3>& vertices_;
  std::vector<std::array<int, 3>>& triangles_;
  std::array<std::vector<int>, 2> layers_;  // vertex ids by lower node and step, layers z and z + 1
};

}  // namespace

void contour_grid(const std::vector<double>& values, const std::array<int, 3>& n, const Vec3& origin, double step,
                  std::vector<Vec3>& vertices, std::vector<std::array<int, 3>>& triangles) {
  Contour<double>(values, n, origin, step, vertices, triangles).run();
}

void contour_grid(const std::vector<float>& values, const std::array<int, 3>& n, const Vec3& origin, double step,
                  std::vector<Vec3>& vertices, std::vector<std::array<int, 3>>& triangles) {
  Contour<float>(values, n, origin, step, vertices, triangles).run();
}

}  // namespace grapebench
