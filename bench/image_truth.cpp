#include "bench/image_truth.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>

#include "bench/case_result.h"
#include "bench/protocols/stereo_pair.h"
#include "sensors/scan.h"
#include "sensors/stereo_rgb.h"
#include "synth/generate.h"
#include "synth/rng.h"
#include "synth/vine_row.h"

namespace grapebench {

CaseScene case_scene(const Scene& scene, const BunchJob& job) {
  CaseScene c;
  std::vector<Bunch> originals;
  if (scene.vine_row) {
    for (std::size_t k = 0; k < vine_row_anchors(*scene.vine_row).size(); ++k)
      originals.push_back(generate_bunch(job.params, derive_seed(job.seed, 0x40000 + k)));
    c.scene_bunch = vine_row(originals, *scene.vine_row, derive_seed(job.seed, 0x4a1e));
  } else {
    originals.push_back(generate_bunch(job.params, job.seed));
    c.scene_bunch = originals.front();
  }
  const std::vector<Vec3> anchors = scene.vine_row ? vine_row_anchors(*scene.vine_row) : std::vector<Vec3>{};
  int berry0 = 0, stem0 = 0;
  for (std::size_t k = 0; k < originals.size(); ++k) {
    CaseBunch b;
    b.original = std::move(originals[k]);
    if (scene.vine_row) {  // as vine_row() hangs it: its peduncle's upper end on the anchor
      const Bunch& o = b.original;
      const Vec3 hang = o.peduncle >= 0 ? o.stems[static_cast<std::size_t>(o.peduncle)].end : o.top;
      b.shift = anchors[k] - hang;
    }
    b.berry0 = berry0, b.stem0 = stem0;
    berry0 += static_cast<int>(b.original.berries.size());
    stem0 += static_cast<int>(b.original.stems.size());
    const double z = first_branch_height(b.original);
    b.branch_z = std::isfinite(z) ? z + b.shift.z() : -std::numeric_limits<double>::infinity();
    b.alone = std::make_unique<RayScene>(b.original);
    c.bunches.push_back(std::move(b));
  }
  return c;
}

namespace {

// The bunch a berry or stem of the scene's bunch belongs to.
int bunch_of(const std::vector<CaseBunch>& bunches, int index, bool stem) {
  for (std::size_t k = bunches.size(); k-- > 0;) {
    if (index >= (stem ? bunches[k].stem0 : bunches[k].berry0)) return static_cast<int>(k);
  }
  return 0;
}

// An instance is (category, index): the bunch's number in the case, the berry's or
// cane's index in the scene, the leaf's fan.
std::int64_t code(int category, std::int64_t index) { return (static_cast<std::int64_t>(category) << 40) | index; }
int code_category(std::int64_t c) { return static_cast<int>(c >> 40); }
std::int64_t code_index(std::int64_t c) { return c & ((std::int64_t{1} << 40) - 1); }

// What a pixel sees, with the instances it belongs to (fine: berry, stalk, leaf, cane,
// or the bunch for its other stems; coarse: its bunch or -1).
struct PixelLabel {
  std::int64_t fine = -1;
  int bunch = -1;
  float depth = 0;  // m along the optical axis, 0: nothing
  std::uint8_t semantic = 0;
};

// Per leaf triangle, its leaf: the leaves are fans about a centre vertex
// (synth/foliage.cpp), numbered in the order their centres first appear.
std::vector<int> leaf_of_triangle(const Foliage& f, std::vector<int>& centre) {
  std::vector<int> out(f.triangles.size());
  std::map<int, int> index;
  for (std::size_t t = 0; t < f.triangles.size(); ++t) {
    auto [it, added] = index.emplace(f.triangles[t][0], static_cast<int>(centre.size()));
    if (added) centre.push_back(f.triangles[t][0]);
    out[t] = it->second;
  }
  return out;
}

std::vector<PixelLabel> label_pixels(const LabelScene& ls, const CaseScene& cs, const Camera& cam) {
  const int W = cam.K.width, H = cam.K.height;
  std::vector<PixelLabel> px(static_cast<std::size_t>(W) * H);
  const RayScene& rays = ls.rays();
  const int stems = static_cast<int>(cs.scene_bunch.stems.size());
  const Eigen::Isometry3d to_cam = cam.pose.inverse();
  for_rows(H, [&](int v0, int v1) {
    std::vector<double> uv(2 * static_cast<std::size_t>(W));
    std::vector<Hit> hits(static_cast<std::size_t>(W));
    const PixelRays at = cam.pixel_rays();
    for (int v = v0; v < v1; ++v) {
      for (int u = 0; u < W; ++u) uv[2 * u] = u + 0.5, uv[2 * u + 1] = v + 0.5;
      rays.intersect_image_points(at, uv.data(), static_cast<std::size_t>(W), hits.data(), true);
      for (int u = 0; u < W; ++u) {
        const Hit& h = hits[static_cast<std::size_t>(u)];
        PixelLabel& p = px[static_cast<std::size_t>(v) * W + u];
        if (!h.valid() || h.part == Part::None) continue;
        p.depth = static_cast<float>((to_cam * h.point).z());
        p.semantic = static_cast<std::uint8_t>(static_cast<int>(h.part) + 1);
        switch (h.part) {
          case Part::Berry:
            p.bunch = bunch_of(cs.bunches, h.primitive, false);
            p.fine = code(kBerry, h.primitive);
            break;
          case Part::Pedicel:
          case Part::Rachis:
          case Part::Peduncle: {
            p.bunch = bunch_of(cs.bunches, h.primitive, true);
            const CaseBunch& cb = cs.bunches[static_cast<std::size_t>(p.bunch)];
            const bool stalk = h.part == Part::Peduncle || (h.part == Part::Rachis && h.point.z() > cb.branch_z &&
                                                            !on_wing(cb.original, h.primitive - cb.stem0));
            p.fine = stalk ? code(kStalk, p.bunch) : code(kBunch, p.bunch);
            break;
          }
          case Part::Leaf:
            p.fine = code(kLeaf, ls.leaf_of_tri[static_cast<std::size_t>(h.primitive)]);
            break;
          case Part::Cane:
            p.fine = code(kCane, h.primitive - stems);
            break;
          default:  // trellis wires and posts, a backdrop: seen, not annotated
            break;
        }
      }
    }
  });
  return px;
}

// The pixel rectangle [u0, u1) x [v0, v1) holding the image of the convex hull of
// `points` (world, m), clipped to the image; the whole image when one is behind the
// camera's plane.
PixelBox hull_pixels(const Camera& cam, const std::vector<Vec3>& points) {
  PixelBox box;
  const Eigen::Isometry3d to_cam = cam.pose.inverse();
  double u0 = 1e300, v0 = 1e300, u1 = -1e300, v1 = -1e300;
  for (const Vec3& w : points) {
    const Vec3 p = to_cam * w;
    if (p.z() <= 1e-6) {
      box.add(0, 0), box.add(cam.K.width - 1, cam.K.height - 1);
      return box;
    }
    const double u = cam.K.fx * p.x() / p.z() + cam.K.cx, v = cam.K.fy * p.y() / p.z() + cam.K.cy;
    u0 = std::min(u0, u), v0 = std::min(v0, v), u1 = std::max(u1, u), v1 = std::max(v1, v);
  }
  // Pixel (u, v) spans [u, u + 1) here (sensors/camera.h): its centre u + 0.5.
  const int a0 = std::max(0, static_cast<int>(std::floor(u0)) - 1), b0 = std::max(0, static_cast<int>(std::floor(v0)) - 1);
  const int a1 = std::min(cam.K.width - 1, static_cast<int>(std::ceil(u1)) + 1),
            b1 = std::min(cam.K.height - 1, static_cast<int>(std::ceil(v1)) + 1);
  if (a0 <= a1 && b0 <= b1) box.add(a0, b0), box.add(a1, b1);
  return box;
}
// The corners of the cube about a ball: its hull holds the ball.
void add_ball(std::vector<Vec3>& points, const Vec3& c, double r) {
  for (int k = 0; k < 8; ++k) points.emplace_back(c + r * Vec3(k & 1 ? 1 : -1, k & 2 ? 1 : -1, k & 4 ? 1 : -1));
}

// The pixels of `box` whose centre ray `hit(ray)` says meets the object: a box-local mask.
template <class HitTest>
void object_mask(const Camera& cam, const PixelBox& box, HitTest hit, std::vector<std::uint8_t>& m) {
  m.assign(box.empty() ? 0 : static_cast<std::size_t>(box.w()) * box.h(), 0);
  if (box.empty()) return;
  const PixelRays at = cam.pixel_rays();
  for (int v = box.v0; v <= box.v1; ++v)
    for (int u = box.u0; u <= box.u1; ++u)
      if (hit(at(u + 0.5, v + 0.5))) m[static_cast<std::size_t>(v - box.v0) * box.w() + (u - box.u0)] = 1;
}

bool ray_sphere(const Ray& r, const Vec3& c, double radius) {
  const Vec3 oc = r.origin - c;
  const double b = oc.dot(r.direction), q = oc.squaredNorm() - radius * radius;
  const double disc = b * b - q;
  return disc >= 0 && -b + std::sqrt(disc) > 0;
}

// Moeller-Trumbore, two-sided.
bool ray_triangle(const Ray& r, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 e1 = b - a, e2 = c - a, p = r.direction.cross(e2);
  const double det = e1.dot(p);
  if (std::abs(det) < 1e-18) return false;
  const double inv = 1 / det;
  const Vec3 s = r.origin - a;
  const double u = s.dot(p) * inv;
  if (u < 0 || u > 1) return false;
  const Vec3 q = s.cross(e1);
  const double v = r.direction.dot(q) * inv;
  if (v < 0 || u + v > 1) return false;
  return e2.dot(q) * inv > 0;
}

}  // namespace

LabelScene label_scene(const Scene& scene, const RayScene& rays) {
  LabelScene ls;
  ls.base = &rays;
  const auto& params = static_cast<const StereoRgb&>(*scene.sensor).params();
  if (params.renderer != StereoRgbParams::Renderer::OpenGl) {
    ls.render.emplace(ray_render_scene(rays, params.appearance));
  }
  ls.leaf_of_tri = leaf_of_triangle(ls.rays().foliage(), ls.leaf_centre);
  ls.leaf_triangles.assign(ls.leaf_centre.size(), {});
  for (std::size_t t = 0; t < ls.leaf_of_tri.size(); ++t)
    ls.leaf_triangles[static_cast<std::size_t>(ls.leaf_of_tri[t])].push_back(static_cast<int>(t));
  return ls;
}

ImageTruth image_truth(const LabelScene& ls, const CaseScene& cs, const Camera& cam, int min_pixels, bool amodal) {
  const int W = cam.K.width, H = cam.K.height;
  ImageTruth out;
  out.width = W, out.height = H;
  const auto t_labels = std::chrono::steady_clock::now();
  const std::vector<PixelLabel> px = label_pixels(ls, cs, cam);

  // Instances: every fine code seen, and each bunch with a pixel; sorted, numbered 1..n.
  std::map<std::int64_t, PixelBox> seen;
  std::map<std::int64_t, std::int64_t> count;
  for (int v = 0; v < H; ++v)
    for (int u = 0; u < W; ++u) {
      const PixelLabel& p = px[static_cast<std::size_t>(v) * W + u];
      if (p.fine >= 0) seen[p.fine].add(u, v), ++count[p.fine];
      if (p.bunch >= 0 && p.fine != code(kBunch, p.bunch)) seen[code(kBunch, p.bunch)].add(u, v), ++count[code(kBunch, p.bunch)];
    }
  std::map<std::int64_t, int> id;
  for (const auto& [c, box] : seen) {
    (void)box;
    id.emplace(c, static_cast<int>(id.size()) + 1);
  }
  if (id.size() > 65535) throw std::runtime_error("more than 65535 instances in one image");


  out.instance_image.assign(px.size(), 0);
  out.semantic.assign(px.size(), 0);
  out.depth.assign(px.size(), 0.0f);
  for (std::size_t i = 0; i < px.size(); ++i) {
    const PixelLabel& p = px[i];
    if (p.fine >= 0) out.instance_image[i] = static_cast<std::uint16_t>(id.at(p.fine));
    else if (p.bunch >= 0) out.instance_image[i] = static_cast<std::uint16_t>(id.at(code(kBunch, p.bunch)));
    out.semantic[i] = p.semantic;
    out.depth[i] = p.depth;
  }
  out.label_seconds = seconds_since(t_labels);
  const auto t_masks = std::chrono::steady_clock::now();
  struct Instance {
    std::int64_t code;
    PixelBox vbox;
  };
  std::vector<Instance> todo;
  for (const auto& [c, vbox] : seen)
    if (count[c] >= min_pixels) todo.push_back({c, vbox});
  std::vector<ImageInstance>& done = out.instances;
  done.resize(todo.size());
  tbb::parallel_for(std::size_t{0}, todo.size(), [&](std::size_t n) {
    const std::int64_t c = todo[n].code;
    const PixelBox& vbox = todo[n].vbox;
    std::vector<std::uint8_t> vis, amo;
    const int cat = code_category(c);
    const std::int64_t index = code_index(c);
    const int iid = id.at(c);
    // Visible mask in its box.
    vis.assign(static_cast<std::size_t>(vbox.w()) * vbox.h(), 0);
    for (int v = vbox.v0; v <= vbox.v1; ++v)
      for (int u = vbox.u0; u <= vbox.u1; ++u) {
        const PixelLabel& p = px[static_cast<std::size_t>(v) * W + u];
        const bool in = p.fine == c || (cat == kBunch && p.bunch == index);
        vis[static_cast<std::size_t>(v - vbox.v0) * vbox.w() + (u - vbox.u0)] = in ? 1 : 0;
      }
    ImageInstance& d = done[n];
    auto finish = [&](std::vector<std::uint8_t>& visible, std::optional<Rle> amodal_rle) {
      d.category = cat, d.index = index, d.id = iid, d.box = vbox;
      if (cat == kBunch || cat == kStalk) d.bunch = static_cast<int>(index);
      if (cat == kBerry) {
        d.bunch = bunch_of(cs.bunches, static_cast<int>(index), false);
        d.berry = static_cast<int>(index) - cs.bunches[static_cast<std::size_t>(d.bunch)].berry0;
      }
      d.visible = rle_encode(visible.data(), vbox.u0, vbox.v0, vbox.w(), vbox.h(), W, H);
      d.amodal = std::move(amodal_rle);
      d.mask = std::move(visible);
    };
    if (!amodal) return finish(vis, std::nullopt);
    // Amodal mask: the object alone, tested in the image box of its hull.
    PixelBox abox;
    std::vector<Vec3> hull;
    if (cat == kBerry) {
      const Berry& b = cs.scene_bunch.berries[static_cast<std::size_t>(index)];
      add_ball(hull, b.centre, b.radius);
      abox = hull_pixels(cam, hull);
      object_mask(cam, abox, [&](const Ray& r) { return ray_sphere(r, b.centre, b.radius); }, amo);
    } else if (cat == kBunch) {
      const CaseBunch& b = cs.bunches[static_cast<std::size_t>(index)];
      const Vec3 lo = b.alone->bunch_min() + b.shift, hi = b.alone->bunch_max() + b.shift;
      for (int q = 0; q < 8; ++q) hull.emplace_back(q & 1 ? hi.x() : lo.x(), q & 2 ? hi.y() : lo.y(), q & 4 ? hi.z() : lo.z());
      abox = hull_pixels(cam, hull);
      object_mask(cam, abox, [&](const Ray& r) {
        return b.alone->intersect(Ray{r.origin - b.shift, r.direction}, true).valid();
      }, amo);
    } else if (cat == kStalk) {
      const CaseBunch& b = cs.bunches[static_cast<std::size_t>(index)];
      std::vector<const Stem*> pieces;
      for (std::size_t s = 0; s < b.original.stems.size(); ++s) {
        const Stem& st = cs.scene_bunch.stems[static_cast<std::size_t>(b.stem0) + s];
        const bool take = st.part == Part::Peduncle || (st.part == Part::Rachis && std::max(st.start.z(), st.end.z()) > b.branch_z &&
                                                        !on_wing(b.original, static_cast<int>(s)));
        if (!take) continue;
        pieces.push_back(&st);
        add_ball(hull, st.start, st.radius), add_ball(hull, st.end, st.radius);
      }
      abox = hull_pixels(cam, hull);
      object_mask(cam, abox, [&](const Ray& r) {
        for (const Stem* st : pieces) {
          double t;
          Vec3 normal;
          if (!ray_cylinder(*st, r.origin, r.direction, 0.0, t, normal)) continue;
          if (st->part == Part::Peduncle || (r.origin + t * r.direction).z() > b.branch_z) return true;
        }
        return false;
      }, amo);
    } else if (cat == kLeaf) {
      const Foliage& f = ls.rays().foliage();
      const auto& tris = ls.leaf_triangles[static_cast<std::size_t>(index)];
      for (int t : tris)
        for (int q : f.triangles[static_cast<std::size_t>(t)]) hull.push_back(f.vertices[static_cast<std::size_t>(q)]);
      abox = hull_pixels(cam, hull);
      object_mask(cam, abox, [&](const Ray& r) {
        for (int t : tris) {
          const auto& tri = f.triangles[static_cast<std::size_t>(t)];
          if (ray_triangle(r, f.vertices[static_cast<std::size_t>(tri[0])], f.vertices[static_cast<std::size_t>(tri[1])],
                           f.vertices[static_cast<std::size_t>(tri[2])]))
            return true;
        }
        return false;
      }, amo);
    } else {  // cane
      const Stem& st = ls.rays().foliage().canes[static_cast<std::size_t>(index)];
      add_ball(hull, st.start, st.radius), add_ball(hull, st.end, st.radius);
      abox = hull_pixels(cam, hull);
      object_mask(cam, abox, [&](const Ray& r) {
        double t;
        Vec3 normal;
        return ray_cylinder(st, r.origin, r.direction, 0.0, t, normal);
      }, amo);
    }
    // Visible within amodal, always (the two tests agree to rounding at the rim).
    PixelBox ubox = abox;
    ubox.add(vbox);
    std::vector<std::uint8_t> merged(static_cast<std::size_t>(ubox.w()) * ubox.h(), 0);
    for (int v = abox.v0; !abox.empty() && v <= abox.v1; ++v)
      for (int u = abox.u0; u <= abox.u1; ++u)
        merged[static_cast<std::size_t>(v - ubox.v0) * ubox.w() + (u - ubox.u0)] = amo[static_cast<std::size_t>(v - abox.v0) * abox.w() + (u - abox.u0)];
    for (int v = vbox.v0; v <= vbox.v1; ++v)
      for (int u = vbox.u0; u <= vbox.u1; ++u)
        merged[static_cast<std::size_t>(v - ubox.v0) * ubox.w() + (u - ubox.u0)] |= vis[static_cast<std::size_t>(v - vbox.v0) * vbox.w() + (u - vbox.u0)];
    const Rle ar = rle_encode(merged.data(), ubox.u0, ubox.v0, ubox.w(), ubox.h(), W, H);
    finish(vis, ar);
  });
  out.mask_seconds = seconds_since(t_masks);
  return out;
}

}  // namespace grapebench
