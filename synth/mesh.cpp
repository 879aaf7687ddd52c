#include "synth/mesh.h"

#include "synth/ball_union.h"
#include "synth/config.h"
#include "synth/stem_geometry.h"

#include <cmath>
#include <cstring>
#include <map>
#include <sstream>

namespace grapebench {

namespace {

// Unit icosphere as a convex polyhedron of triangles.
ConvexPolyhedron icosphere(int level) {
  std::vector<Vec3> v;
  std::vector<std::array<int, 3>> f;
  unit_icosphere(level, v, f);
  ConvexPolyhedron p;
  for (const auto& tri : f) {
    PolyFace face;
    face.vertices = {v[tri[0]], v[tri[1]], v[tri[2]]};
    face.normal = (v[tri[1]] - v[tri[0]]).cross(v[tri[2]] - v[tri[0]]).normalized();
    p.faces.push_back(std::move(face));
  }
  return p;
}

// Appends pieces to a mesh, welding identical positions within one piece.
struct Builder {
  TriMesh& mesh;
  std::map<std::array<double, 3>, int> index;
  void begin_piece() { index.clear(); }
  int vertex(const Vec3& x) {
    const std::array<double, 3> key{x.x(), x.y(), x.z()};
    auto it = index.find(key);
    if (it != index.end()) return it->second;
    mesh.vertices.push_back(x);
    return index[key] = static_cast<int>(mesh.vertices.size()) - 1;
  }
  void tri(int a, int b, int c, Part part, int berry, bool internal) {
    if (a == b || b == c || a == c) return;
    mesh.faces.push_back({a, b, c});
    mesh.face_part.push_back(part);
    mesh.face_berry.push_back(berry);
    mesh.face_internal.push_back(internal ? 1 : 0);
  }
};

void add_berry(Builder& out, const Bunch& bunch, int i, const ConvexPolyhedron& unit) {
  const Berry& b = bunch.berries[i];
  std::vector<Vec3> centres;
  std::vector<double> radii;
  for (const auto& x : bunch.berries) {
    centres.push_back(x.centre);
    radii.push_back(x.radius);
  }
  std::vector<HalfSpace> hs;
  if (!power_cell_halfspaces(centres, radii, i, hs)) return;
  if (b.pedicel >= 0) {
    const Stem& ped = bunch.stems[b.pedicel];
    const Vec3 d = (ped.end - ped.start).normalized();
    hs.push_back({-d, -pedicel_entry_offset(ped, b)});
  }
  ConvexPolyhedron p = unit;
  for (auto& f : p.faces) {
    for (auto& v : f.vertices) v = b.radius * v;  // relative to the berry centre
  }
  for (const auto& h : hs) {
    if (h.offset >= b.radius) continue;
    clip(p, h, 0);
    if (p.empty()) return;
  }
  out.begin_piece();
  for (const auto& f : p.faces) {
    std::vector<int> idx;
    for (const auto& v : f.vertices) idx.push_back(out.vertex(b.centre + v));
    for (std::size_t k = 1; k + 1 < idx.size(); ++k) {
      out.tri(idx[0], idx[k], idx[k + 1], Part::Berry, i, f.tag >= 0);
    }
  }
}

void add_stem(Builder& out, const Bunch& bunch, int si, int sides) {
  const Stem& s = bunch.stems[si];
  const Vec3 d = (s.end - s.start).normalized();
  double length = (s.end - s.start).norm();
  bool end_internal = false;
  if (s.berry >= 0) {  // a pedicel's piece ends where its rim enters the berry
    const Berry& b = bunch.berries[s.berry];
    length = (b.centre - s.start).dot(d) + pedicel_entry_offset(s, b);
    end_internal = true;
  }
  Vec3 e1, e2;
  perpendicular_basis(d, e1, e2);
  auto dir = [&](int k) {
    const double phi = 2 * M_PI * k / sides;
    return Vec3(std::cos(phi) * e1 + std::sin(phi) * e2);
  };
  out.begin_piece();
  // Start surface: flat for a root, on the parent's surface for a child, shared with
  // the segment below for a stacked rachis segment.
  const int rings = std::max(1, sides / 4);
  std::vector<std::vector<int>> start(rings + 1, std::vector<int>(sides));
  auto start_point = [&](double u, int k) {
    const Vec3 p = s.start + u * s.radius * dir(k);
    if (s.parent < 0) return p;
    return Vec3(p + std::min(length, exit_distance(bunch.stems[s.parent], p, d)) * d);
  };
  const int apex = out.vertex(start_point(0, 0));
  for (int j = 1; j <= rings; ++j) {
    for (int k = 0; k < sides; ++k) start[j][k] = out.vertex(start_point(static_cast<double>(j) / rings, k));
  }
  const bool start_internal = s.parent >= 0 || s.stacked_on >= 0;
  for (int k = 0; k < sides; ++k) {
    const int k1 = (k + 1) % sides;
    out.tri(apex, start[1][k1], start[1][k], s.part, -1, start_internal);
    for (int j = 1; j < rings; ++j) {
      out.tri(start[j][k], start[j + 1][k1], start[j + 1][k], s.part, -1, start_internal);
      out.tri(start[j][k], start[j][k1], start[j + 1][k1], s.part, -1, start_internal);
    }
  }
  const Vec3 end_centre = s.start + length * d;
  std::vector<int> end(sides);
  for (int k = 0; k < sides; ++k) end[k] = out.vertex(end_centre + s.radius * dir(k));
  const int end_apex = out.vertex(end_centre);
  for (int k = 0; k < sides; ++k) {
    const int k1 = (k + 1) % sides;
    out.tri(start[rings][k], start[rings][k1], end[k1], s.part, -1, false);
    out.tri(start[rings][k], end[k1], end[k], s.part, -1, false);
    out.tri(end_apex, end[k], end[k1], s.part, -1, end_internal);
  }
}

void put_u8(std::string& s, unsigned char v) { s.push_back(static_cast<char>(v)); }
template <class T>
void put(std::string& s, T v) {
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  s.append(b, sizeof(T));
}
unsigned char byte(float c) { return static_cast<unsigned char>(std::lround(std::clamp(c, 0.0f, 1.0f) * 255)); }

}  // namespace

Exported exported(const TriMesh& m) {
  Exported e;
  e.vertex_map.assign(m.vertices.size(), -1);
  for (int f = 0; f < static_cast<int>(m.faces.size()); ++f) {
    if (m.face_internal[f]) continue;
    e.faces.push_back(f);
    for (int v : m.faces[f]) {
      if (e.vertex_map[v] < 0) {
        e.vertex_map[v] = static_cast<int>(e.vertices.size());
        e.vertices.push_back(v);
        e.vertex_colour.push_back(label_colour(m.face_part[f], m.face_berry[f]));
      }
    }
  }
  return e;
}

void unit_icosphere(int level, std::vector<Vec3>& v, std::vector<std::array<int, 3>>& f) {
  const double t = (1 + std::sqrt(5.0)) / 2;
  v = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
       {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  for (auto& x : v) x.normalize();
  f = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11}, {1, 5, 9},  {5, 11, 4},
       {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6},  {3, 6, 8},
       {3, 8, 9},  {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (int l = 0; l < level; ++l) {
    std::map<std::pair<int, int>, int> mid;
    auto midpoint = [&](int a, int b) {
      const auto key = std::minmax(a, b);
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      v.push_back((v[a] + v[b]).normalized());
      return mid[key] = static_cast<int>(v.size()) - 1;
    };
    std::vector<std::array<int, 3>> g;
    for (const auto& tri : f) {
      const int a = midpoint(tri[0], tri[1]), b = midpoint(tri[1], tri[2]), c = midpoint(tri[2], tri[0]);
      g.push_back({tri[0], a, c});
      g.push_back({tri[1], b, a});
      g.push_back({tri[2], c, b});
      g.push_back({a, b, c});
    }
    f = std::move(g);
  }
}

TriMesh bunch_mesh(const Bunch& bunch, const MeshOptions& o) {
  if (o.sphere_subdivisions < 0 || o.sphere_subdivisions > 6) {
    throw InputError("mesh: sphere_subdivisions must be in [0, 6]");
  }
  if (o.tube_sides < 3 || o.tube_sides > 256) throw InputError("mesh: tube_sides must be in [3, 256]");
  TriMesh mesh;
  Builder out{mesh, {}};
  const ConvexPolyhedron unit = icosphere(o.sphere_subdivisions);
  for (int i = 0; i < static_cast<int>(bunch.berries.size()); ++i) add_berry(out, bunch, i, unit);
  for (int i = 0; i < static_cast<int>(bunch.stems.size()); ++i) add_stem(out, bunch, i, o.tube_sides);
  return mesh;
}

double enclosed_volume(const TriMesh& m) {
  if (m.vertices.empty()) return 0;
  Vec3 o = Vec3::Zero();
  for (const auto& v : m.vertices) o += v;
  o /= static_cast<double>(m.vertices.size());
  double v6 = 0;
  for (const auto& f : m.faces) {
    v6 += (m.vertices[f[0]] - o).dot((m.vertices[f[1]] - o).cross(m.vertices[f[2]] - o));
  }
  return v6 / 6.0;
}

Rgb label_colour(Part part, int berry) {
  switch (part) {
    case Part::Berry: {
      // Golden-ratio hues, so neighbouring ids differ; kept in the red-violet-blue
      // range so berries never look like stems.
      const double h = std::fmod(0.55 + 0.618033988749895 * std::max(berry, 0), 1.0) * 0.45 + 0.55;
      const double x = h * 6;
      const int sector = static_cast<int>(x) % 6;
      const double f = x - std::floor(x);
      const double v = 0.85, s = 0.65, p = v * (1 - s), q = v * (1 - s * f), t = v * (1 - s * (1 - f));
      const double rgb[6][3] = {{v, t, p}, {q, v, p}, {p, v, t}, {p, q, v}, {t, p, v}, {v, p, q}};
      return {static_cast<float>(rgb[sector][0]), static_cast<float>(rgb[sector][1]),
              static_cast<float>(rgb[sector][2])};
    }
    case Part::Pedicel: return {0.75f, 0.85f, 0.20f};
    case Part::Rachis: return {0.20f, 0.60f, 0.15f};
    case Part::Peduncle: return {0.50f, 0.32f, 0.12f};
    case Part::Background: return {0.55f, 0.55f, 0.55f};
    case Part::Leaf: return {0.10f, 0.45f, 0.10f};
    case Part::Cane: return {0.40f, 0.28f, 0.16f};
    case Part::None: return {0, 0, 0};
  }
  return {1, 1, 1};
}

std::string ply_bytes(const TriMesh& m) {
  const Exported e = exported(m);
  std::ostringstream h;
  h << "ply\nformat binary_little_endian 1.0\n"
    << "comment grapebench bunch mesh, metres; part: 0 berry 1 pedicel 2 rachis 3 peduncle\n"
    << "element vertex " << e.vertices.size() << "\n"
    << "property double x\nproperty double y\nproperty double z\n"
    << "property uchar red\nproperty uchar green\nproperty uchar blue\n"
    << "element face " << e.faces.size() << "\n"
    << "property list uchar int vertex_indices\n"
    << "property uchar red\nproperty uchar green\nproperty uchar blue\n"
    << "property uchar part\nproperty int berry\nend_header\n";
  std::string s = h.str();
  for (std::size_t k = 0; k < e.vertices.size(); ++k) {
    const Vec3& v = m.vertices[e.vertices[k]];
    put(s, v.x());  // double: rounding the closed union to float can make faces cross
    put(s, v.y());
    put(s, v.z());
    put_u8(s, byte(e.vertex_colour[k].r));
    put_u8(s, byte(e.vertex_colour[k].g));
    put_u8(s, byte(e.vertex_colour[k].b));
  }
  for (int f : e.faces) {
    put_u8(s, 3);
    for (int v : m.faces[f]) put<std::int32_t>(s, e.vertex_map[v]);
    const Rgb c = label_colour(m.face_part[f], m.face_berry[f]);
    put_u8(s, byte(c.r));
    put_u8(s, byte(c.g));
    put_u8(s, byte(c.b));
    put_u8(s, static_cast<unsigned char>(m.face_part[f]));
    put<std::int32_t>(s, m.face_berry[f]);
  }
  return s;
}

std::string obj_material_library() {
  std::ostringstream s;
  s << "# grapebench part label colours\n";
  for (Part p : kAllParts) {
    const Rgb c = p == Part::Berry ? Rgb{0.55f, 0.10f, 0.45f} : label_colour(p, -1);
    s << "newmtl " << part_name(p) << "\nKd " << c.r << " " << c.g << " " << c.b << "\nKa 0 0 0\n\n";
  }
  return s.str();
}

std::string obj_text(const TriMesh& m, const std::string& mtl_name) {
  const Exported e = exported(m);
  std::ostringstream s;
  s.precision(9);
  s << "# grapebench bunch mesh, metres\nmtllib " << mtl_name << "\n";
  for (int v : e.vertices) {
    const Vec3& x = m.vertices[v];
    s << "v " << x.x() << " " << x.y() << " " << x.z() << "\n";
  }
  std::string group;
  for (int f : e.faces) {
    const Part p = m.face_part[f];
    const std::string g = p == Part::Berry ? "berry_" + std::to_string(m.face_berry[f]) : std::string(part_name(p));
    if (g != group) {
      s << "g " << g << "\nusemtl " << part_name(p) << "\n";
      group = g;
    }
    s << "f " << e.vertex_map[m.faces[f][0]] + 1 << " " << e.vertex_map[m.faces[f][1]] + 1 << " "
      << e.vertex_map[m.faces[f][2]] + 1 << "\n";
  }
  return s.str();
}

}  // namespace grapebench
