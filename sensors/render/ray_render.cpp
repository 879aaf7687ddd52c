#include "sensors/render/ray_render.h"

#include <atomic>
#include <cmath>
#include <memory>
#include <optional>

#include "sensors/render/huge_page_buffer.h"
#include "sensors/render/row_copies.h"
#include "sensors/sensor.h"
#include "synth/rng.h"

namespace grapebench {

namespace {

using C3 = Eigen::Array3d;
C3 c3(const Rgb& c) { return {c.r, c.g, c.b}; }
double luminance(const C3& c) { return 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2]; }

// An orthonormal frame about a unit vector, branch-free (Duff et al. 2017, "Building
// an Orthonormal Basis, Revisited", JCGT 6(1)); Eigen's unitOrthogonal took a hypot.
void frame(const Vec3& n, Vec3& t, Vec3& b) {
  const double sign = std::copysign(1.0, n.z()), a = -1.0 / (sign + n.z()), c = n.x() * n.y() * a;
  t = Vec3(1.0 + sign * n.x() * n.x() * a, sign * c, -sign * n.x());
  b = Vec3(c, sign + n.y() * n.y() * a, -n.y());
}
// The azimuth's sine and cosine in single precision (sincosf: a direction good to
// 1e-7 rad, and half the time of the double sincos, 3 % of a foliage image).
void azimuth(double u, double& c, double& s) {
  const float phi = static_cast<float>(2 * M_PI * u);
  c = std::cos(phi), s = std::sin(phi);
}
Vec3 cosine_direction(const Vec3& n, double u1, double u2) {
  Vec3 t, b;
  frame(n, t, b);
  double cp, sp;
  azimuth(u2, cp, sp);
  const double r = std::sqrt(u1);
  return (r * cp * t + r * sp * b + std::sqrt(std::max(0.0, 1 - u1)) * n).normalized();
}
// Uniform in the cone of half-angle acos(cos_max) about `axis`, whose frame is t, b.
Vec3 cone_direction(const Vec3& axis, const Vec3& t, const Vec3& b, double cos_max, double u1, double u2) {
  double cp, sp;
  azimuth(u2, cp, sp);
  const double c = 1 - u1 * (1 - cos_max), s = std::sqrt(std::max(0.0, 1 - c * c));
  return (s * cp * t + s * sp * b + c * axis).normalized();
}
Vec3 cone_direction(const Vec3& axis, double cos_max, double u1, double u2) {
  Vec3 t, b;
  frame(axis, t, b);
  return cone_direction(axis, t, b, cos_max, u1, u2);
}

// GGX microfacet lobe with Smith-Schlick shadowing and Schlick's Fresnel (Walter et al.
// 2007; Karis 2013): BRDF value for light from wi seen from wo, both unit, about n.
double ggx(const Vec3& n, const Vec3& wi, const Vec3& wo, double alpha, double f0) {
  const double ni = n.dot(wi), no = n.dot(wo);
  if (ni <= 0 || no <= 0 || f0 <= 0) return 0;
  const Vec3 h = (wi + wo).normalized();
  const double nh = std::max(0.0, n.dot(h)), a2 = alpha * alpha;
  const double dd = nh * nh * (a2 - 1) + 1;
  const double D = a2 / (M_PI * dd * dd);
  const double k = alpha / 2;
  const double G = ni / (ni * (1 - k) + k) * no / (no * (1 - k) + k);
  const double F = f0 + (1 - f0) * std::pow(1 - std::max(0.0, wo.dot(h)), 5);
  return D * G * F / (4 * ni * no);
}

// What one camera ray (one sample of a pixel) saw; how each light lights it is in a
// SampleLight of its own. The pixel's radiance is direct + albedo * sky_front +
// transmittance * sky_back: the sky rays' incoming radiance is kept apart so that it
// can be filtered across pixels.
struct Sample {
  std::uint64_t key = 0;  // 0 sky, 1 ground, else the object (part and instance): edges are where it changes
  float depth = 0;        // m along the optical axis (0: sky)
  Vec3 normal = Vec3::Zero();
  C3 albedo = C3::Zero(), trans = C3::Zero();
  bool sky_reused = false;  // an edge sample on its pixel's centre object: the centre's sky light stands for it
};
struct SampleLight {
  C3 direct = C3::Zero(), sky_front = C3::Zero(), sky_back = C3::Zero();
};

// What a pixel keeps between the passes, in single precision (the double Sample and
// five more arrays were 280 bytes a pixel: a fresh 800 x 600 image spent a fifth of
// its time in the kernel's page faults and in zero-filling them): 56 bytes, and 36 a
// light in a PixelLight. Pass 2 replaces the centre sample's terms by the pixel's
// means in place. Trivially destructible, so both live in huge pages
// (sensors/render/huge_page_buffer.h).
struct Pixel {
  std::uint64_t key;
  float depth;
  Eigen::Vector3f normal;
  Eigen::Array3f albedo, trans;
  // sky_stride 2, a pixel casting no sky rays of its own: the share of its surface
  // samples that take its upsampled light (front and back then hold the mean of the
  // others' own rays).
  float share;
};
struct PixelLight {
  Eigen::Array3f direct, front, back;
};
static_assert(sizeof(Pixel) == 56 && sizeof(PixelLight) == 36);
Pixel compact(const Sample& s) {
  return {s.key, s.depth, s.normal.cast<float>(), s.albedo.cast<float>(), s.trans.cast<float>(), 1.0f};
}
PixelLight compact(const SampleLight& s) {
  return {s.direct.cast<float>(), s.sky_front.cast<float>(), s.sky_back.cast<float>()};
}

// Per light, what the shading reads of it, once an image.
struct LightTerms {
  explicit LightTerms(const Illumination& light)
      : sky(light),
        sun_dir(light.sun_direction.normalized()),
        sun_cos_max(std::cos(0.5 * std::max(light.sun_size_deg, 1e-3) * M_PI / 180)),
        sun_rgb(light.sun * c3(light.sun_colour)),
        sun_on(light.sun > 0) {
    frame(sun_dir, sun_t, sun_b);  // the sun's frame, once an image instead of once a sample (the same bits)
  }
  SkyModel sky;
  Vec3 sun_dir, sun_t, sun_b;
  double sun_cos_max;
  C3 sun_rgb;
  bool sun_on;
};

// A batch of shadow rays (segments) and whether each is blocked.
struct Segments {
  std::vector<Vec3> from, to;
  std::vector<char> blocked;
};
// Per-thread buffers of a batch; sun_of, sun_used and bounce_of hold sample (or sky
// ray) i's light l at i L + l. The shadow rays of each light are cast as a batch of
// their own, in the order one light alone casts them: Embree's packets then hold the
// same rays, and a ray grazing an edge is decided as it is alone (with the lights'
// rays mixed in one batch, one case of seed 001's 1,368 pairs came out otherwise).
struct Scratch {
  std::vector<Hit> hits, sky_hits;
  std::vector<Vec3> mfrom, mto;
  std::vector<char> mblocked, ground;
  std::vector<Ray> sky_rays;
  std::vector<Material> mat, sky_mat;
  std::vector<int> sun_of, front_of, back_of, mir_of, bounce_of;
  std::vector<Vec3> sun_used, mir_dir;
  std::vector<Segments> sun, bounce;  // per light
};

}  // namespace

RayRenderScene ray_render_scene(const RayScene& scene, const AppearanceParams& look) {
  RayRenderScene out;
  out.scene = &scene;
  const Foliage& src = scene.foliage();
  const RowCopies rows = row_copies(src, look, scene.bunch_min().z() - look.ground_below);
  if (!rows.foliage.empty()) {
    Foliage all = src;
    const int base = static_cast<int>(all.vertices.size());
    all.vertices.insert(all.vertices.end(), rows.foliage.vertices.begin(), rows.foliage.vertices.end());
    for (const auto& t : rows.foliage.triangles) all.triangles.push_back({base + t[0], base + t[1], base + t[2]});
    all.triangle_colour.insert(all.triangle_colour.end(), rows.foliage.triangle_colour.begin(),
                               rows.foliage.triangle_colour.end());
    all.canes.insert(all.canes.end(), rows.foliage.canes.begin(), rows.foliage.canes.end());
    out.merged.emplace(scene.bunch(), scene.background(), all);
  }
  return out;
}

RayRenderResult ray_render(const RayScene& scene, const Camera& cam, const Illumination& light,
                           const AppearanceParams& look, const PhotoCameraParams& camera, double focal_length,
                           std::uint64_t seed) {
  return ray_render(ray_render_scene(scene, look), cam, light, look, camera, focal_length, seed);
}

RayRenderResult ray_render(const RayRenderScene& prepared, const Camera& cam, const Illumination& light,
                           const AppearanceParams& look, const PhotoCameraParams& camera, double focal_length,
                           std::uint64_t seed) {
  return std::move(ray_render(prepared, cam, std::span<const Illumination>(&light, 1), look, camera, focal_length, seed)[0]);
}

std::vector<RayRenderResult> ray_render(const RayRenderScene& prepared, const Camera& cam,
                                        std::span<const Illumination> lights, const AppearanceParams& look,
                                        const PhotoCameraParams& camera, double focal_length, std::uint64_t seed) {
  const int W = cam.K.width, H = cam.K.height, S = camera.samples;
  const std::size_t nlight = lights.size();
  const std::size_t npix = static_cast<std::size_t>(W) * H;
  // One Embree scene: the bunch, its foliage and the row copies after it (a leaf
  // triangle past the scene's own is a copy), so every ray is cast once.
  const RayScene& scene = *prepared.scene;
  const Foliage& src = scene.foliage();
  const RayScene& rs = prepared.rays();
  const Foliage& fol = rs.foliage();
  const std::size_t src_tri = src.triangles.size();

  const double ground_z = scene.bunch_min().z() - look.ground_below;
  std::vector<LightTerms> T;
  T.reserve(nlight);
  for (const Illumination& light : lights) T.emplace_back(light);
  double leaf_mean = 0;
  for (const Rgb& c : src.triangle_colour) leaf_mean += luminance(c3(c));
  leaf_mean = src.triangle_colour.empty() ? 1.0 : std::max(1e-6, leaf_mean / static_cast<double>(src_tri));

  const auto material = [&](const Hit& h) -> Material {
    switch (h.part) {
      case Part::Berry:
        return berry_material(look, h.colour);
      case Part::Leaf: {
        // A copy's point is read on the scene's own leaf (the same barycentric
        // coordinates), so every copy of a leaf carries the same texture and veins.
        const auto& tri = fol.triangles[static_cast<std::size_t>(h.primitive)];
        const auto at = [&](int k) -> const Vec3& { return fol.vertices[static_cast<std::size_t>(tri[k])]; };
        const Vec3 wn = (at(1) - at(0)).cross(at(2) - at(0));
        const bool upper = wn.dot(h.normal) > 0;
        const auto& st = src.triangles[static_cast<std::size_t>(h.primitive) % src_tri];
        const auto sv = [&](int k) -> const Vec3& { return src.vertices[static_cast<std::size_t>(st[k])]; };
        Vec3 p = h.point;
        if (static_cast<std::size_t>(h.primitive) >= src_tri) {
          const Vec3 e0 = at(1) - at(0), e1 = at(2) - at(0), d = h.point - at(0);
          const double d00 = e0.dot(e0), d01 = e0.dot(e1), d11 = e1.dot(e1), d20 = d.dot(e0), d21 = d.dot(e1);
          const double den = d00 * d11 - d01 * d01;
          const double b1 = den != 0 ? (d11 * d20 - d01 * d21) / den : 0, b2 = den != 0 ? (d00 * d21 - d01 * d20) / den : 0;
          // Copy vertex v repeats the scene's vertex (v - n) % n (n the scene's count);
          // a mirrored copy's triangles list them in another order.
          const std::size_t nv = src.vertices.size();
          const auto orig = [&](int k) -> const Vec3& {
            return src.vertices[(static_cast<std::size_t>(tri[k]) - nv) % nv];
          };
          p = orig(0) + b1 * (orig(1) - orig(0)) + b2 * (orig(2) - orig(0));
        }
        const Vec3 sn = (sv(1) - sv(0)).cross(sv(2) - sv(0)).normalized();
        return leaf_material(look, p, sv(0), src.vertices[static_cast<std::size_t>(st[0]) + 1], sn,
                             luminance(c3(h.colour)) / leaf_mean, upper);
      }
      default:
        return wood_material(look, h.point, h.colour);
    }
  };
  // What an edge is made of: the part and its instance (a berry, a stem or cane, a
  // leaf by its fan's centre vertex).
  const auto object_key = [&](const Hit& h) {
    std::uint64_t inst = static_cast<std::uint64_t>(h.primitive + 1);
    if (h.part == Part::Berry) inst = static_cast<std::uint64_t>(h.berry + 1);
    if (h.part == Part::Leaf) inst = static_cast<std::uint64_t>(fol.triangles[static_cast<std::size_t>(h.primitive)][0] + 1);
    return 2 + (static_cast<std::uint64_t>(h.part) << 40) + inst;
  };
  // Radiance leaving a surface (material m, normal n) met by a sky ray (the one
  // bounce) under light t: the sun where a shadow ray from it reaches the sun
  // (`sunlit`), and half the sky without a test.
  const auto bounce = [&](const Material& m, const Vec3& n, bool sunlit, const LightTerms& t) -> C3 {
    const double cs = sunlit ? n.dot(t.sun_dir) : 0.0;
    C3 l = c3(m.albedo) * (0.5 * t.sky.irradiance + std::max(0.0, cs) * t.sun_rgb) / M_PI;
    l += c3(m.transmittance) * std::max(0.0, -cs) * t.sun_rgb / M_PI;
    return l;
  };
  const auto ground_radiance = [&](bool sunlit, const LightTerms& t) -> C3 {
    return c3(look.ground_reflectance) * (t.sky.irradiance + (sunlit ? std::max(0.0, t.sun_dir.z()) : 0.0) * t.sun_rgb) /
           M_PI;
  };
  const std::uint64_t s_pix = derive_seed(seed, 11), s_sun = derive_seed(seed, 13), s_sky = derive_seed(seed, 14),
                      s_mir = derive_seed(seed, 15);
  const Vec3 optical_axis = cam.pose.linear().col(2);
  const int K = camera.sky_samples;
  std::vector<std::uint64_t> sky_stream(static_cast<std::size_t>(K), s_sky);  // the first as before
  for (int k = 1; k < K; ++k) sky_stream[static_cast<std::size_t>(k)] = derive_seed(s_sky, static_cast<std::uint64_t>(k));

  // Shades a batch of camera rays under every light; `ids` number the samples for the
  // hashed draws. A sample that meets the object `reuse_key` names (its pixel's centre
  // object) casts no sky rays: the centre's estimate of the same surface's sky light, a
  // pixel away, stands for it (and is filtered over 5 x 5 pixels after): 3.57 -> 3.15
  // rays a pixel in a foliage view (docs/sensors.md, "Speed"). A sample `sky_off`
  // marks casts none either (sky_stride 2: its pixel takes the grid's light). `lit`
  // gets sample i's light l at i L + l.
  const auto shade = [&](const std::vector<Ray>& rays, const std::vector<std::uint64_t>& ids, std::vector<Sample>& out,
                         std::vector<SampleLight>& lit, Scratch& z, const std::uint64_t* reuse_key,
                         const char* sky_off) {
    const std::size_t n = rays.size(), nl = n * nlight;
    std::uint64_t cast = n;
    rs.intersect(rays, z.hits);
    out.assign(n, Sample{});
    lit.assign(nl, SampleLight{});
    z.mat.resize(n);
    z.sun_of.assign(nl, -1), z.front_of.assign(n, -1), z.back_of.assign(n, -1), z.mir_of.assign(n, -1);
    z.sun_used.resize(nl), z.mir_dir.resize(n);
    z.ground.assign(n, 0);
    z.sky_rays.clear(), z.mfrom.clear(), z.mto.clear();
    z.sun.resize(nlight), z.bounce.resize(nlight);
    for (Segments& g : z.sun) g.from.clear(), g.to.clear();
    for (Segments& g : z.bounce) g.from.clear(), g.to.clear();
    for (std::size_t i = 0; i < n; ++i) {
      const Ray& r = rays[i];
      const Hit& h = z.hits[i];
      Sample& s = out[i];
      const std::uint64_t id = ids[i];
      Vec3 p, nrm;
      bool transmits = false;
      if (h.valid()) {
        z.mat[i] = material(h);
        p = h.point;
        nrm = h.normal;
        s.key = object_key(h);
        s.albedo = c3(z.mat[i].albedo);
        s.trans = c3(z.mat[i].transmittance);
        transmits = s.trans.sum() > 0;
      } else if (r.direction.z() < 0 && (ground_z - r.origin.z()) / r.direction.z() > 0) {
        p = r.origin + (ground_z - r.origin.z()) / r.direction.z() * r.direction;
        nrm = Vec3::UnitZ();
        s.key = 1;
        z.ground[i] = 1;
      } else {
        for (std::size_t l = 0; l < nlight; ++l) {
          const LightTerms& t = T[l];
          C3& d = lit[i * nlight + l].direct;
          d = t.sky.radiance(r.direction);
          if (r.direction.dot(t.sun_dir) >= t.sun_cos_max) d += t.sun_rgb / (2 * M_PI * (1 - t.sun_cos_max));  // the disc
        }
        continue;
      }
      s.normal = nrm;
      s.depth = static_cast<float>((p - r.origin).dot(optical_axis));
      // The sun: towards a point of its disc, from the lit side (from the far side for
      // light through leaves and berries). The same draw under every light.
      const double su = hashed_uniform(s_sun, 2 * id), sv = hashed_uniform(s_sun, 2 * id + 1);
      for (std::size_t l = 0; l < nlight; ++l) {
        const LightTerms& t = T[l];
        const Vec3 sd = cone_direction(t.sun_dir, t.sun_t, t.sun_b, t.sun_cos_max, su, sv);
        z.sun_used[i * nlight + l] = sd;
        const double cs = nrm.dot(sd);
        if (t.sun_on && (cs > 0 || (transmits && cs < 0))) {
          Vec3 start = p + (cs > 0 ? 1e-4 : -1e-4) * nrm;
          if (cs < 0 && h.part == Part::Berry && h.berry >= 0) {
            const Berry& b = scene.bunch().berries[static_cast<std::size_t>(h.berry)];
            start = b.centre + (b.radius + 1e-4) * sd;  // the berry's sunlit side
          }
          Segments& g = z.sun[l];
          z.sun_of[i * nlight + l] = static_cast<int>(g.from.size());
          g.from.push_back(start);
          g.to.push_back(start + 50.0 * sd);
        }
      }
      if (z.ground[i]) continue;
      s.sky_reused = (reuse_key != nullptr && reuse_key[i] == s.key) || (sky_off != nullptr && sky_off[i]);
      // Sky rays, cosine-weighted about each face that reflects (front) or transmits
      // (back): sky_samples of them, consecutive, the first from the stream s_sky.
      if (!s.sky_reused) {
        z.front_of[i] = static_cast<int>(z.sky_rays.size());
        for (int k = 0; k < K; ++k)
          z.sky_rays.push_back({p + 1e-4 * nrm, cosine_direction(nrm, hashed_uniform(sky_stream[k], 4 * id),
                                                                 hashed_uniform(sky_stream[k], 4 * id + 1))});
      }
      if (transmits && !s.sky_reused) {
        // The far face: a leaf's other side; a berry's antipode (what the flesh
        // passes on to this point), sampled about the opposite normal.
        Vec3 back_from = p - 1e-4 * nrm;
        if (h.part == Part::Berry && h.berry >= 0) {
          const Berry& b = scene.bunch().berries[static_cast<std::size_t>(h.berry)];
          back_from = b.centre - (b.radius + 1e-4) * nrm;
        }
        z.back_of[i] = static_cast<int>(z.sky_rays.size());
        for (int k = 0; k < K; ++k)
          z.sky_rays.push_back({back_from, cosine_direction(-nrm, hashed_uniform(sky_stream[k], 4 * id + 2),
                                                            hashed_uniform(sky_stream[k], 4 * id + 3))});
      }
      // A mirror ray of glossy surfaces, blurred by the lobe's roughness (a cone of
      // half-angle about alpha): the sky or ground it sees, or nothing.
      if (z.mat[i].specular > 0) {
        const Vec3 wo = -r.direction;
        Vec3 d = 2 * nrm.dot(wo) * nrm - wo;
        d = cone_direction(d.normalized(), std::cos(std::min(1.2, z.mat[i].roughness)), hashed_uniform(s_mir, 2 * id),
                           hashed_uniform(s_mir, 2 * id + 1));
        if (d.dot(nrm) > 0) {
          z.mir_of[i] = static_cast<int>(z.mfrom.size());
          z.mir_dir[i] = d;
          z.mfrom.push_back(p + 1e-4 * nrm);
          z.mto.push_back(p + 50.0 * d);
        }
      }
    }
    for (Segments& g : z.sun) {
      rs.occluded(g.from, g.to, g.blocked);
      cast += g.from.size();
    }
    rs.intersect(z.sky_rays, z.sky_hits);
    rs.occluded(z.mfrom, z.mto, z.mblocked);
    cast += z.sky_rays.size() + z.mfrom.size();
    // What the sky rays met, and whether each light's sun reaches it (from the face it
    // turns to the sun).
    const std::size_t ns = z.sky_rays.size();
    z.sky_mat.resize(ns);
    z.bounce_of.assign(ns * nlight, -1);
    for (std::size_t k = 0; k < ns; ++k) {
      const Hit& a = z.sky_hits[k];
      if (!a.valid()) continue;
      z.sky_mat[k] = material(a);
      const bool transmits = a.part == Part::Leaf || a.part == Part::Berry;
      for (std::size_t l = 0; l < nlight; ++l) {
        const LightTerms& t = T[l];
        if (!t.sun_on) continue;
        const double cs = a.normal.dot(t.sun_dir);
        if (cs <= 0 && !transmits) continue;
        Vec3 start = a.point + (cs > 0 ? 1e-4 : -1e-4) * a.normal;
        if (cs <= 0 && a.part == Part::Berry && a.berry >= 0) {
          const Berry& b = scene.bunch().berries[static_cast<std::size_t>(a.berry)];
          start = b.centre + (b.radius + 1e-4) * t.sun_dir;  // the berry's sunlit side
        }
        Segments& g = z.bounce[l];
        z.bounce_of[k * nlight + l] = static_cast<int>(g.from.size());
        g.from.push_back(start);
        g.to.push_back(start + 50.0 * t.sun_dir);
      }
    }
    for (Segments& g : z.bounce) {
      rs.occluded(g.from, g.to, g.blocked);
      cast += g.from.size();
    }
    const auto incoming = [&](int k, std::size_t l) -> C3 {
      const std::size_t kk = static_cast<std::size_t>(k);
      const Ray& sr = z.sky_rays[kk];
      const Hit& a = z.sky_hits[kk];
      const int b = z.bounce_of[kk * nlight + l];
      if (a.valid()) return bounce(z.sky_mat[kk], a.normal, b >= 0 && !z.bounce[l].blocked[static_cast<std::size_t>(b)], T[l]);
      if (sr.direction.z() < 0) return ground_radiance(true, T[l]);
      return T[l].sky.radiance(sr.direction);
    };
    const auto mean_incoming = [&](int first, std::size_t l) -> C3 {
      C3 sum = C3::Zero();
      for (int k = 0; k < K; ++k) sum += incoming(first + k, l);
      return sum / K;
    };
    for (std::size_t i = 0; i < n; ++i) {
      const Sample& s = out[i];
      if (s.key == 0) continue;
      const Vec3 wo = -rays[i].direction;
      for (std::size_t l = 0; l < nlight; ++l) {
        const LightTerms& t = T[l];
        SampleLight& o = lit[i * nlight + l];
        const int so = z.sun_of[i * nlight + l];
        const bool sunlit = so >= 0 && !z.sun[l].blocked[static_cast<std::size_t>(so)];
        if (z.ground[i]) {
          o.direct = ground_radiance(sunlit, t);
          continue;
        }
        if (sunlit) {
          const Vec3& sd = z.sun_used[i * nlight + l];
          const double cs = s.normal.dot(sd);
          if (cs > 0) o.direct += (s.albedo / M_PI + ggx(s.normal, sd, wo, z.mat[i].roughness, z.mat[i].specular)) * cs * t.sun_rgb;
          else o.direct += s.trans / M_PI * (-cs) * t.sun_rgb;
        }
        // Cosine-weighted sampling: the irradiance estimate is pi L, the reflected
        // radiance rho / pi times that.
        if (z.front_of[i] >= 0) o.sky_front = mean_incoming(z.front_of[i], l);
        if (z.back_of[i] >= 0) o.sky_back = mean_incoming(z.back_of[i], l);
        if (z.mir_of[i] >= 0 && !z.mblocked[static_cast<std::size_t>(z.mir_of[i])]) {
          const Vec3& d = z.mir_dir[i];
          const double f = z.mat[i].specular + (1 - z.mat[i].specular) * std::pow(1 - std::max(0.0, s.normal.dot(wo)), 5);
          o.direct += f * (d.z() < 0 ? ground_radiance(true, t) : t.sky.radiance(d));
        }
      }
    }
    return cast;
  };

  // Pass 1: one ray through each pixel's centre (the exact labels' ray). Every pixel
  // is written by the pass, so the buffers are left uninitialised. At sky_stride 2 only
  // the grid's pixels (u and v even: the anchors) cast sky rays. Pixel i's light l is
  // at centre_lit[i L + l].
  const HugePageMemory centre_memory = huge_page_buffer(npix * (sizeof(Pixel) + nlight * sizeof(PixelLight)));
  Pixel* const centre = static_cast<Pixel*>(centre_memory.get());
  std::uninitialized_default_construct_n(centre, npix);
  PixelLight* const centre_lit = reinterpret_cast<PixelLight*>(centre + npix);
  std::uninitialized_default_construct_n(centre_lit, npix * nlight);
  std::atomic<std::uint64_t> rays{0};
  const PixelRays pr = cam.pixel_rays();
  const bool strided = camera.sky_stride > 1;
  const auto is_anchor = [](int u, int v) { return ((u | v) & 1) == 0; };
  // The centre rays of the pixels `take` (u, v) selects, a row a batch; `sky_off` (u,
  // v): that pixel casts no sky rays.
  const auto centre_pass = [&](const auto& take, const auto& sky_off) {
    for_rows(H, [&](int r0, int r1) {
      Scratch z;
      std::vector<Ray> batch;
      std::vector<std::uint64_t> ids;
      std::vector<Sample> got;
      std::vector<SampleLight> got_lit;
      std::vector<char> off;
      std::vector<int> at;
      for (int v = r0; v < r1; ++v) {
        batch.clear(), ids.clear(), off.clear(), at.clear();
        for (int u = 0; u < W; ++u) {
          if (!take(u, v)) continue;
          batch.push_back(pr(u + 0.5, v + 0.5));
          ids.push_back((static_cast<std::uint64_t>(v) * W + u) * 128);
          off.push_back(sky_off(u, v));
          at.push_back(u);
        }
        if (batch.empty()) continue;
        rays += shade(batch, ids, got, got_lit, z, nullptr, off.data());
        for (std::size_t k = 0; k < at.size(); ++k) {
          const std::size_t i = static_cast<std::size_t>(v) * W + at[k];
          centre[i] = compact(got[k]);
          for (std::size_t l = 0; l < nlight; ++l) centre_lit[i * nlight + l] = compact(got_lit[k * nlight + l]);
        }
      }
    });
  };
  centre_pass([](int, int) { return true; }, [&](int u, int v) { return strided && !is_anchor(u, v); });
  // Whether neighbour o may lend pixel c its sky light, and with which weight before
  // the taper: the same part class within 3 sd of depth (sd 1 % of the depth), then
  // (n.n')^8 exp(-dz^2 / 2); 0 for none. Split so that the exponentials run in a loop
  // of their own (below).
  struct Tap {
    std::size_t j;
    float normal_term, exponent, taper;
  };
  const auto admit = [](const Pixel& c, const Pixel& o, float inv_sd, float& normal_term, float& exponent) {
    if (o.key < 2 || (o.key >> 40) != (c.key >> 40)) return false;
    const float dz = (o.depth - c.depth) * inv_sd;
    if (dz * dz > 9) return false;  // beyond 3 sd: no weight worth an exp
    const float nd = std::max(0.0f, c.normal.dot(o.normal)), n2 = nd * nd, n4 = n2 * n2;
    normal_term = n4 * n4, exponent = -0.5f * dz * dz;
    return true;
  };
  // sky_stride 2: the anchors within 2 px of (u, v) that may lend it their light,
  // tapered by (3 - |du|)(3 - |dv|) (a tent over the grid); a normal term below 1e-30
  // is none, so that every weight found is > 0 after the exponential. `first_only`:
  // stop at the first (whether there is any).
  const auto anchor_taps = [&](int u, int v, Tap* taps, bool first_only) {
    const Pixel& c = centre[static_cast<std::size_t>(v) * W + u];
    const float inv_sd = 1.0f / (0.01f * c.depth + 1e-4f);
    int m = 0;
    for (int vv = std::max(0, (v - 1) & ~1); vv <= std::min(H - 1, v + 2); vv += 2)
      for (int uu = std::max(0, (u - 1) & ~1); uu <= std::min(W - 1, u + 2); uu += 2) {
        const std::size_t j = static_cast<std::size_t>(vv) * W + uu;
        float nt, ex;
        if (!admit(c, centre[j], inv_sd, nt, ex) || !(nt > 1e-30f)) continue;
        taps[m++] = {j, nt, ex, static_cast<float>((3 - std::abs(uu - u)) * (3 - std::abs(vv - v)))};
        if (first_only) return m;
      }
    return m;
  };
  // sky_stride 2: a surface pixel off the grid with no anchor to lend it light (a stem
  // thinner than the grid, a leaf's tip) casts its own sky rays: its centre ray shaded
  // again with the same draws, so it differs from pass 1 in its sky light alone.
  std::vector<char> orphan(strided ? npix : 0, 0);
  if (strided) {
    for_rows(H, [&](int r0, int r1) {
      Tap taps[9];
      for (int v = r0; v < r1; ++v)
        for (int u = 0; u < W; ++u) {
          const std::size_t i = static_cast<std::size_t>(v) * W + u;
          orphan[i] = centre[i].key >= 2 && !is_anchor(u, v) && anchor_taps(u, v, taps, true) == 0;
        }
    });
    centre_pass([&](int u, int v) { return orphan[static_cast<std::size_t>(v) * W + u] != 0; },
                [](int, int) { return false; });
  }
  // Whether pixel i holds a sky estimate of its own (its rays, or none needed).
  const auto own_sky = [&](int u, int v, std::size_t i) {
    return !strided || centre[i].key < 2 || is_anchor(u, v) || orphan[i];
  };
  // Pass 2: pixels where what is seen changes within the 3 x 3 neighbourhood are
  // anti-aliased with samples^2 more rays, stratified and jittered over the pixel.
  for_rows(H, [&](int r0, int r1) {
    Scratch z;
    std::vector<Ray> batch;
    std::vector<std::uint64_t> ids, reuse;
    std::vector<Sample> got;
    std::vector<SampleLight> got_lit;
    std::vector<int> owner;
    std::vector<C3> d(nlight), f(nlight), b(nlight), cf(nlight), cb(nlight);
    for (int v = r0; v < r1; ++v) {
      batch.clear(), ids.clear(), reuse.clear(), owner.clear();
      for (int u = 0; u < W; ++u) {
        const std::size_t i = static_cast<std::size_t>(v) * W + u;
        bool edge = false;
        for (int dv = -1; dv <= 1 && !edge; ++dv)
          for (int du = -1; du <= 1 && !edge; ++du) {
            const int uu = u + du, vv = v + dv;
            if (uu < 0 || vv < 0 || uu >= W || vv >= H) continue;
            edge = centre[static_cast<std::size_t>(vv) * W + uu].key != centre[i].key;
          }
        if (!edge || S < 2) continue;
        for (int s = 0; s < S * S; ++s) {
          const std::uint64_t id = i * 128 + 1 + static_cast<std::uint64_t>(s);
          batch.push_back(pr(u + (s % S + hashed_uniform(s_pix, 2 * id)) / S, v + (s / S + hashed_uniform(s_pix, 2 * id + 1)) / S));
          ids.push_back(id);
          reuse.push_back(centre[i].key);
          owner.push_back(u);
        }
      }
      if (!batch.empty()) rays += shade(batch, ids, got, got_lit, z, reuse.data(), nullptr);
      // Every pixel's mean over its samples (the centre, and the extra ones at edges).
      std::size_t k = 0;
      for (int u = 0; u < W; ++u) {
        const std::size_t i = static_cast<std::size_t>(v) * W + u;
        Pixel& c = centre[i];
        if (k >= owner.size() || owner[k] != u) continue;  // no extra samples: the centre's terms stand
        PixelLight* const cl = centre_lit + i * nlight;
        for (std::size_t l = 0; l < nlight; ++l) {
          cf[l] = cl[l].front.cast<double>(), cb[l] = cl[l].back.cast<double>();
          d[l] = cl[l].direct.cast<double>(), f[l] = cf[l], b[l] = cb[l];
        }
        C3 a = c.albedo.cast<double>(), t = c.trans.cast<double>();
        double m = 1, surfaces = c.key >= 2 ? 1 : 0;
        if (own_sky(u, v, i)) {
          for (; k < owner.size() && owner[k] == u; ++k) {
            const Sample& g = got[k];
            a += g.albedo, t += g.trans;
            for (std::size_t l = 0; l < nlight; ++l) {
              const SampleLight& gl = got_lit[k * nlight + l];
              d[l] += gl.direct;
              f[l] += g.sky_reused ? cf[l] : gl.sky_front, b[l] += g.sky_reused ? cb[l] : gl.sky_back;
            }
            m += 1;
            surfaces += g.key >= 2;
          }
        } else {
          // No light of the centre's yet (it is upsampled after the filter): the
          // samples that reuse it are counted, the others' own rays averaged.
          double reused = 1, others = 0;
          for (std::size_t l = 0; l < nlight; ++l) f[l] = C3::Zero(), b[l] = C3::Zero();
          for (; k < owner.size() && owner[k] == u; ++k) {
            const Sample& g = got[k];
            a += g.albedo, t += g.trans;
            for (std::size_t l = 0; l < nlight; ++l) d[l] += got_lit[k * nlight + l].direct;
            m += 1;
            if (g.key < 2) continue;
            if (g.sky_reused) {
              reused += 1;
            } else {
              for (std::size_t l = 0; l < nlight; ++l) {
                const SampleLight& gl = got_lit[k * nlight + l];
                f[l] += gl.sky_front, b[l] += gl.sky_back;
              }
              others += 1;
            }
          }
          c.share = static_cast<float>(reused / (reused + others));
          surfaces = std::max(1.0, others);
        }
        // albedo is the pixel's mean (the coverage w times the surfaces' mean), the sky
        // light the mean over the samples that met a surface: their product is w rho L
        // (a mean over every sample would give w^2 rho L, a dark fringe at silhouettes).
        const double s = std::max(1.0, surfaces);
        c.albedo = (a / m).cast<float>(), c.trans = (t / m).cast<float>();
        for (std::size_t l = 0; l < nlight; ++l) {
          cl[l].direct = (d[l] / m).cast<float>();
          cl[l].front = (f[l] / s).cast<float>(), cl[l].back = (b[l] / s).cast<float>();
        }
      }
    }
  });
  // Pass 3: the sky rays' incoming radiance (one ray a pixel: noisy) filtered over 5 x 5
  // pixels of the same part and instance class, similar depth and normal (a joint
  // bilateral filter, as real-time ambient occlusion is denoised), then the image.
  // With sky_filter > 1 the filtered light is filtered again at steps 2, 4, 8 with the
  // B3-spline taps of the edge-avoiding a-trous transform (Dammertz et al. 2010,
  // "Edge-avoiding A-Trous wavelet transform for fast global illumination filtering").
  // Pixel (u, v)'s sky light under each light l filtered at `step` from front(j, l) /
  // back(j, l) (box taps in the first pass, B3-spline taps after), over the
  // neighbours `usable` admits, into f[l] and b[l]: the taps and their weights once,
  // the sums per light. In single precision throughout (the terms are floats already;
  // the double conversions were a third of the pass). In loops of their own, so that
  // no accumulator is live across the calls to exp (all vector registers are the
  // caller's to save): the tests, the exponentials, then the sums in tap order, each
  // operation as one loop would do it, so the image is the same to the bit. At
  // sky_stride 2 the passes run on the grid (steps 2, 4, 8 px from an anchor meet
  // anchors only).
  const auto filter = [&](int u, int v, int step, bool box, const auto& front, const auto& back, const auto& usable,
                          Eigen::Array3f* f, Eigen::Array3f* b) {
    static constexpr float spline[5] = {1.0f / 16, 1.0f / 4, 3.0f / 8, 1.0f / 4, 1.0f / 16};
    const std::size_t i = static_cast<std::size_t>(v) * W + u;
    const Pixel& c = centre[i];
    for (std::size_t l = 0; l < nlight; ++l) f[l] = front(i, l), b[l] = back(i, l);
    if (c.key < 2) return;
    const float inv_sd = 1.0f / (0.01f * c.depth + 1e-4f);
    Tap tap[25];
    int m = 0;
    for (int dv = -2; dv <= 2; ++dv) {
      const int vv = v + step * dv;
      if (vv < 0 || vv >= H) continue;
      for (int du = -2; du <= 2; ++du) {
        const int uu = u + step * du;
        if (uu < 0 || uu >= W) continue;
        const std::size_t j = static_cast<std::size_t>(vv) * W + uu;
        float nt, ex;
        if (!usable(j) || !admit(c, centre[j], inv_sd, nt, ex)) continue;
        tap[m++] = {j, nt, ex, spline[du + 2] * spline[dv + 2]};
      }
    }
    float e[25];
    for (int k = 0; k < m; ++k) e[k] = std::exp(tap[k].exponent);
    float w[25];
    std::size_t js[25];
    int mw = 0;
    float sw = 0;
    for (int k = 0; k < m; ++k) {
      float wk = tap[k].normal_term * e[k];
      if (wk == 0) continue;
      if (!box) wk *= tap[k].taper;
      w[mw] = wk, js[mw++] = tap[k].j;
      sw += wk;
    }
    if (!(sw > 0)) return;
    for (std::size_t l = 0; l < nlight; ++l) {
      Eigen::Array3f sf = Eigen::Array3f::Zero(), sb = Eigen::Array3f::Zero();
      for (int k = 0; k < mw; ++k) sf += w[k] * front(js[k], l), sb += w[k] * back(js[k], l);
      f[l] = sf / sw, b[l] = sb / sw;
    }
  };
  const auto raw_front = [&](std::size_t j, std::size_t l) -> const Eigen::Array3f& { return centre_lit[j * nlight + l].front; };
  const auto raw_back = [&](std::size_t j, std::size_t l) -> const Eigen::Array3f& { return centre_lit[j * nlight + l].back; };
  const auto any = [](std::size_t) { return true; };
  // Passes before the last into buffers of their own, two sets used in turn (none at
  // sky_filter 1): 2 MiB pages, uninitialised, since every pixel is written (fresh 4 KiB
  // pages cost a fault and a clearing each: 5,600 of them an image at 800 x 600). At
  // sky_stride 2 every pass goes to a buffer (its anchors only), the upsampling after.
  // Pixel j's light l at j L + l.
  const int buffered = strided ? camera.sky_filter : camera.sky_filter - 1;
  const int sets = std::min(buffered, 2);
  const std::size_t plane = npix * nlight;
  const HugePageMemory lit_memory =
      sets > 0 ? huge_page_buffer(static_cast<std::size_t>(2 * sets) * plane * sizeof(Eigen::Array3f)) : nullptr;
  Eigen::Array3f* const lit_base = static_cast<Eigen::Array3f*>(lit_memory.get());
  const Eigen::Array3f* lit_front = nullptr;
  const Eigen::Array3f* lit_back = nullptr;
  const auto lit_f = [&](std::size_t j, std::size_t l) -> const Eigen::Array3f& { return lit_front[j * nlight + l]; };
  const auto lit_b = [&](std::size_t j, std::size_t l) -> const Eigen::Array3f& { return lit_back[j * nlight + l]; };
  // Pass p (from 1) filters at step stride 2^(p-1), the first from the raw light.
  const int stride = camera.sky_stride;
  const auto filter_pass = [&](int pass, int u, int v, Eigen::Array3f* f, Eigen::Array3f* b) {
    const int step = stride << (pass - 1);
    if (pass == 1) filter(u, v, step, true, raw_front, raw_back, any, f, b);
    else filter(u, v, step, false, lit_f, lit_b, any, f, b);
  };
  for (int pass = 1; pass <= buffered; ++pass) {
    Eigen::Array3f* const nf = lit_base + static_cast<std::size_t>(2 * ((pass - 1) % 2)) * plane;
    Eigen::Array3f* const nb = nf + plane;
    std::uninitialized_default_construct_n(nf, 2 * plane);
    for_rows(H, [&](int r0, int r1) {
      for (int v = (r0 + stride - 1) / stride * stride; v < r1; v += stride) {
        for (int u = 0; u < W; u += stride) {
          const std::size_t i = static_cast<std::size_t>(v) * W + u;
          filter_pass(pass, u, v, nf + i * nlight, nb + i * nlight);
        }
      }
    });
    lit_front = nf, lit_back = nb;
  }
  // sky_stride 2: a pixel's light from the grid, and from its own samples.
  const auto strided_light = [&](int u, int v, Eigen::Array3f* f, Eigen::Array3f* b) {
    const std::size_t i = static_cast<std::size_t>(v) * W + u;
    const Pixel& c = centre[i];
    const PixelLight* const cl = centre_lit + i * nlight;
    if (c.key < 2) {
      for (std::size_t l = 0; l < nlight; ++l) f[l] = cl[l].front, b[l] = cl[l].back;
    } else if (is_anchor(u, v)) {
      for (std::size_t l = 0; l < nlight; ++l) f[l] = lit_front[i * nlight + l], b[l] = lit_back[i * nlight + l];
    } else if (orphan[i]) {
      // Its own rays, filtered over the other such pixels (the anchors lend none).
      const auto own = [&](std::size_t j) { return orphan[j] != 0; };
      filter(u, v, 1, true, raw_front, raw_back, own, f, b);
    } else {
      Tap taps[9];
      const int m = anchor_taps(u, v, taps, false);
      float e[9], w[9];
      for (int k = 0; k < m; ++k) e[k] = std::exp(taps[k].exponent);
      float sw = 0;
      for (int k = 0; k < m; ++k) {
        w[k] = taps[k].normal_term * e[k] * taps[k].taper;
        sw += w[k];
      }
      for (std::size_t l = 0; l < nlight; ++l) {
        Eigen::Array3f sf = Eigen::Array3f::Zero(), sb = Eigen::Array3f::Zero();
        for (int k = 0; k < m; ++k) {
          const std::size_t j = taps[k].j * nlight + l;
          sf += w[k] * lit_front[j], sb += w[k] * lit_back[j];
        }
        f[l] = c.share * sf / sw + (1 - c.share) * cl[l].front, b[l] = c.share * sb / sw + (1 - c.share) * cl[l].back;
      }
    }
  };
  std::vector<RayRenderResult> out(nlight);
  for (RayRenderResult& o : out) o.linear.assign(3 * npix, 0.0f);
  for_rows(H, [&](int r0, int r1) {
    std::vector<Eigen::Array3f> f(nlight), b(nlight);
    for (int v = r0; v < r1; ++v) {
      for (int u = 0; u < W; ++u) {
        const std::size_t i = static_cast<std::size_t>(v) * W + u;
        const Pixel& c = centre[i];
        if (strided) strided_light(u, v, f.data(), b.data());
        else filter_pass(camera.sky_filter, u, v, f.data(), b.data());
        for (std::size_t l = 0; l < nlight; ++l) {
          const PixelLight& cl = centre_lit[i * nlight + l];
          const C3 px = M_PI * (cl.direct.cast<double>() + c.albedo.cast<double>() * f[l].cast<double>() +
                                c.trans.cast<double>() * b[l].cast<double>());  // radiance times pi
          for (int ch = 0; ch < 3; ++ch) out[l].linear[3 * i + ch] = static_cast<float>(px[ch]);
        }
      }
    }
  });
  // Pass 4: defocus of a thin lens at f_number focused at focus_distance: each pixel
  // spread over its circle of confusion, c = (f / N) f / (s - f) |z - s| / z on the
  // sensor (f / fx per pixel), gathered (a pixel takes the neighbours whose circle
  // covers it, each weighted by one over its circle's area); radius capped at 8 px.
  // The circles depend on depth alone: their weights once, the sums per light.
  if (camera.f_number > 0) {
    const double f = focal_length, s = camera.focus_distance > 0
                                           ? camera.focus_distance
                                           : std::max(0.05, (cam.pose.inverse() * scene.bunch_centre()).z());
    const double k = (f / camera.f_number) * cam.K.fx / std::max(s - f, 1e-6);  // c in px = k |z - s| / z
    std::vector<float> radius(npix);
    float rmax = 0;
    for (std::size_t i = 0; i < npix; ++i) {
      const double z = centre[i].depth;
      radius[i] = static_cast<float>(std::min(8.0, 0.5 * (z > 0 ? k * std::abs(z - s) / z : k)));
      rmax = std::max(rmax, radius[i]);
    }
    if (rmax >= 0.5f) {
      std::vector<std::vector<float>> sharp(nlight);
      for (std::size_t l = 0; l < nlight; ++l) sharp[l] = out[l].linear;
      const int R = static_cast<int>(std::ceil(rmax));
      // Each 16 x 16 tile gathers over the largest circle within R px of it, not the
      // image's: a neighbour farther than that covers none of its pixels, so the taps
      // and their order are the same (the same bits) and in-focus tiles take 3 x 3.
      constexpr int T16 = 16;
      const int tw = (W + T16 - 1) / T16, th = (H + T16 - 1) / T16;
      std::vector<float> tile_max(static_cast<std::size_t>(tw) * th, 0.5f);
      for (int v = 0; v < H; ++v)
        for (int u = 0; u < W; ++u) {
          float& m = tile_max[static_cast<std::size_t>(v / T16) * tw + u / T16];
          m = std::max(m, radius[static_cast<std::size_t>(v) * W + u]);
        }
      const int reach = (R + T16 - 1) / T16;  // tiles within R px
      std::vector<int> tile_r(tile_max.size());
      for (int ty = 0; ty < th; ++ty)
        for (int tx = 0; tx < tw; ++tx) {
          float m = 0.5f;
          for (int y = std::max(0, ty - reach); y <= std::min(th - 1, ty + reach); ++y)
            for (int x = std::max(0, tx - reach); x <= std::min(tw - 1, tx + reach); ++x)
              m = std::max(m, tile_max[static_cast<std::size_t>(y) * tw + x]);
          tile_r[static_cast<std::size_t>(ty) * tw + tx] = std::min(R, static_cast<int>(std::ceil(m)));
        }
      for_rows(H, [&](int r0, int r1) {
        std::vector<double> acc(3 * nlight);
        for (int v = r0; v < r1; ++v)
          for (int u = 0; u < W; ++u) {
            const int Rt = tile_r[static_cast<std::size_t>(v / T16) * tw + u / T16];
            std::fill(acc.begin(), acc.end(), 0.0);
            double sw = 0;
            for (int dv = -Rt; dv <= Rt; ++dv)
              for (int du = -Rt; du <= Rt; ++du) {
                const int uu = u + du, vv = v + dv;
                if (uu < 0 || vv < 0 || uu >= W || vv >= H) continue;
                const std::size_t j = static_cast<std::size_t>(vv) * W + uu;
                const double r = std::max(0.5f, radius[j]);
                if (du * du + dv * dv > r * r) continue;
                const double w = 1 / (r * r);
                for (std::size_t l = 0; l < nlight; ++l)
                  for (int ch = 0; ch < 3; ++ch) acc[3 * l + ch] += w * sharp[l][3 * j + ch];
                sw += w;
              }
            const std::size_t i = static_cast<std::size_t>(v) * W + u;
            for (std::size_t l = 0; l < nlight; ++l)
              for (int ch = 0; ch < 3; ++ch) out[l].linear[3 * i + ch] = static_cast<float>(acc[3 * l + ch] / sw);
          }
      });
    }
  }
  for (RayRenderResult& o : out) o.rays = rays;
  return out;
}

}  // namespace grapebench
