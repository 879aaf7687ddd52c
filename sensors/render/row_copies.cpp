#include "sensors/render/row_copies.h"

namespace grapebench {

RowCopies row_copies(const Foliage& f, const AppearanceParams& a, double ground_z) {
  RowCopies out;
  out.foliage.cane_colour = f.cane_colour;
  out.foliage.trellis_colour = f.trellis_colour;
  out.source_triangles = f.triangles.size();
  out.source_vertices = f.vertices.size();
  if (f.empty()) return out;
  Vec3 lo = f.vertices.empty() ? f.canes[0].start : f.vertices[0], hi = lo;
  for (const Vec3& v : f.vertices) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
  for (const Stem& s : f.canes) lo = lo.cwiseMin(s.start).cwiseMin(s.end), hi = hi.cwiseMax(s.start).cwiseMax(s.end);
  const double cx = 0.5 * (lo.x() + hi.x());
  const int along = a.vine_spacing > 0 ? 3 : 0;
  const int behind = a.row_spacing > 0 ? a.rows_behind : 0;
  Foliage& o = out.foliage;
  for (int j = 0; j <= behind; ++j) {
    for (int i = -along; i <= along; ++i) {
      if (i == 0 && j == 0) continue;
      const bool mirror = (i + j) % 2 != 0;
      const Vec3 shift(i * a.vine_spacing, j * a.row_spacing, 0);
      const auto place = [&](const Vec3& p) {
        Vec3 q = p;
        if (mirror) q.x() = 2 * cx - q.x();
        return Vec3(q + shift);
      };
      const int base = static_cast<int>(o.vertices.size());
      for (const Vec3& v : f.vertices) o.vertices.push_back(place(v));
      for (std::size_t t = 0; t < f.triangles.size(); ++t) {
        const auto& tri = f.triangles[t];
        // A mirror image reverses the winding: swapped back, so the upper face stays upper.
        if (mirror) o.triangles.push_back({base + tri[0], base + tri[2], base + tri[1]});
        else o.triangles.push_back({base + tri[0], base + tri[1], base + tri[2]});
        o.triangle_colour.push_back(f.triangle_colour[t]);
      }
      for (Stem s : f.canes) {
        s.start = place(s.start);
        s.end = place(s.end);
        o.canes.push_back(s);
      }
    }
  }
  // Posts midway between vine i and i + 1, every `post_every` vines, each row behind a vine on.
  if (a.post_every > 0 && a.vine_spacing > 0 && ground_z < hi.z()) {
    for (int j = 0; j <= behind; ++j) {
      for (int i = -along - 1; i <= along; ++i) {
        if (((i + j) % a.post_every + a.post_every) % a.post_every != 0) continue;
        if (j == 0 && (i == -1 || i == 0)) continue;  // beside the scene's own vine
        Stem post;
        post.start = Vec3(cx + (i + 0.5) * a.vine_spacing, 0.5 * (lo.y() + hi.y()) + j * a.row_spacing, ground_z);
        post.end = Vec3(post.start.x(), post.start.y(), hi.z() + 0.05);
        post.radius = a.post_radius;
        post.part = Part::Background;
        o.canes.push_back(post);
      }
    }
  }
  return out;
}

}  // namespace grapebench
