#include "sensors/ray_scene.h"

#include "synth/config.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace grapebench {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

void on_embree_error(void* user, RTCError code, const char* message) {
  auto* last = static_cast<std::string*>(user);
  *last = "Embree error " + std::to_string(static_cast<int>(code)) + ": " + (message ? message : "");
}



void stem_bounds(const RTCBoundsFunctionArguments* args) {
  const Stem& s = static_cast<const Stem*>(args->geometryUserPtr)[args->primID];
  const Vec3 lo = s.start.cwiseMin(s.end) - Vec3::Constant(s.radius);
  const Vec3 hi = s.start.cwiseMax(s.end) + Vec3::Constant(s.radius);
  RTCBounds* b = args->bounds_o;
  // Rounded outwards so float bounds never cut the exact double cylinder.
  b->lower_x = std::nextafter(static_cast<float>(lo.x()), -INFINITY);
  b->lower_y = std::nextafter(static_cast<float>(lo.y()), -INFINITY);
  b->lower_z = std::nextafter(static_cast<float>(lo.z()), -INFINITY);
  b->upper_x = std::nextafter(static_cast<float>(hi.x()), INFINITY);
  b->upper_y = std::nextafter(static_cast<float>(hi.y()), INFINITY);
  b->upper_z = std::nextafter(static_cast<float>(hi.z()), INFINITY);
}

// Lane i of an Embree ray packet against one stem.
bool stem_hit(const Stem& s, RTCRayN* ray, unsigned N, unsigned i, double& t, Vec3& n) {
  const Vec3 o(RTCRayN_org_x(ray, N, i), RTCRayN_org_y(ray, N, i), RTCRayN_org_z(ray, N, i));
  const Vec3 d(RTCRayN_dir_x(ray, N, i), RTCRayN_dir_y(ray, N, i), RTCRayN_dir_z(ray, N, i));
  return ray_cylinder(s, o, d, RTCRayN_tnear(ray, N, i), t, n);
}

void stem_intersect(const RTCIntersectFunctionNArguments* args) {
  const Stem& s = static_cast<const Stem*>(args->geometryUserPtr)[args->primID];
  const unsigned N = args->N;
  RTCRayN* ray = RTCRayHitN_RayN(args->rayhit, N);
  RTCHitN* hit = RTCRayHitN_HitN(args->rayhit, N);
  for (unsigned i = 0; i < N; ++i) {
    if (args->valid[i] != -1) continue;
    double t;
    Vec3 n;
    const bool hit_stem = stem_hit(s, ray, N, i, t, n);
    if (!hit_stem || t >= RTCRayN_tfar(ray, N, i)) continue;
    RTCRayN_tfar(ray, N, i) = static_cast<float>(t);
    RTCHitN_Ng_x(hit, N, i) = static_cast<float>(n.x());
    RTCHitN_Ng_y(hit, N, i) = static_cast<float>(n.y());
    RTCHitN_Ng_z(hit, N, i) = static_cast<float>(n.z());
    RTCHitN_u(hit, N, i) = 0;
    RTCHitN_v(hit, N, i) = 0;
    RTCHitN_primID(hit, N, i) = args->primID;
    RTCHitN_geomID(hit, N, i) = args->geomID;
    RTCHitN_instID(hit, N, i, 0) = args->context->instID[0];
  }
}

void stem_occluded(const RTCOccludedFunctionNArguments* args) {
  const Stem& s = static_cast<const Stem*>(args->geometryUserPtr)[args->primID];
  const unsigned N = args->N;
  RTCRayN* ray = args->ray;
  for (unsigned i = 0; i < N; ++i) {
    if (args->valid[i] != -1) continue;
    double t;
    Vec3 n;
    const bool hit_stem = stem_hit(s, ray, N, i, t, n);
    if (hit_stem && t < RTCRayN_tfar(ray, N, i)) {
      RTCRayN_tfar(ray, N, i) = -INFINITY;  // Embree's convention for "occluded"
    }
  }
}


// One lane of a ray packet: origin and direction (any length), the whole ray range.
void set_lane(RTCRayHit16& rh, std::size_t k, float ox, float oy, float oz, float dx, float dy, float dz) {
  rh.ray.org_x[k] = ox;
  rh.ray.org_y[k] = oy;
  rh.ray.org_z[k] = oz;
  rh.ray.dir_x[k] = dx;
  rh.ray.dir_y[k] = dy;
  rh.ray.dir_z[k] = dz;
  rh.ray.tnear[k] = 0;
  rh.ray.tfar[k] = INFINITY;
  rh.ray.time[k] = 0;
  rh.ray.mask[k] = 0xFFFFFFFFu;  // Debian's Embree has ray masks enabled
  rh.ray.flags[k] = 0;
  rh.ray.id[k] = static_cast<unsigned>(k);
  rh.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0][k] = RTC_INVALID_GEOMETRY_ID;
}

// Loads up to 16 rays into a packet; lanes past `n` are masked off.
void load_packet(const Ray* rays, std::size_t n, RTCRayHit16& rh, int* valid) {
  for (std::size_t k = 0; k < 16; ++k) {
    valid[k] = k < n ? -1 : 0;
    const Ray& r = rays[std::min(k, n - 1)];
    set_lane(rh, k, static_cast<float>(r.origin.x()), static_cast<float>(r.origin.y()), static_cast<float>(r.origin.z()),
             static_cast<float>(r.direction.x()), static_cast<float>(r.direction.y()), static_cast<float>(r.direction.z()));
  }
}

}  // namespace

bool ray_cylinder(const Stem& s, const Vec3& o, const Vec3& d, double tnear, double& t, Vec3& normal) {
  const Vec3 axis = s.end - s.start;
  const double len = axis.norm();
  const Vec3 w = axis / len;
  const Vec3 rel = o - s.start;
  const double s0 = rel.dot(w), dw = d.dot(w);
  double t0 = -kInf, t1 = kInf;
  Vec3 n0 = Vec3::Zero();
  if (std::abs(dw) > 1e-15) {
    double ta = -s0 / dw, tb = (len - s0) / dw;
    Vec3 na = -w, nb = w;
    if (ta > tb) {
      std::swap(ta, tb);
      std::swap(na, nb);
    }
    t0 = ta;
    t1 = tb;
    n0 = na;
  } else if (s0 < 0 || s0 > len) {
    return false;
  }
  const Vec3 q = rel - s0 * w, dp = d - dw * w;
  const double A = dp.squaredNorm(), B = q.dot(dp), C = q.squaredNorm() - s.radius * s.radius;
  if (A > 1e-30) {
    const double disc = B * B - A * C;
    if (disc < 0) return false;
    const double sq = std::sqrt(disc);
    const double ca = (-B - sq) / A, cb = (-B + sq) / A;
    if (ca > t0) {
      t0 = ca;
      const Vec3 p = q + ca * dp;
      n0 = p / std::max(p.norm(), 1e-300);
    }
    t1 = std::min(t1, cb);
  } else if (C > 0) {
    return false;
  }
  if (t0 > t1 || t0 <= tnear) return false;
  t = t0;
  normal = n0;
  return true;
}

RayScene::State::~State() {
  if (scene) rtcReleaseScene(scene);
  if (device) rtcReleaseDevice(device);
}

RayScene::RayScene(const Bunch& bunch, std::optional<BackgroundPlane> background, const Foliage& foliage)
    : state_(std::make_shared<State>()), background_(background) {
  State& st = *state_;
  st.bunch = bunch;
  st.foliage = foliage;
  st.stems = bunch.stems;
  st.stems.insert(st.stems.end(), foliage.canes.begin(), foliage.canes.end());
  for (const auto& t : foliage.triangles) {
    for (int v : t) {
      if (v < 0 || static_cast<std::size_t>(v) >= foliage.vertices.size()) {
        throw InputError("ray scene: a leaf triangle names vertex " + std::to_string(v) + " of " +
                         std::to_string(foliage.vertices.size()));
      }
    }
  }
  if (foliage.triangle_colour.size() != foliage.triangles.size()) {
    throw InputError("ray scene: leaf triangles and their colours differ in count");
  }
  if (bunch.berries.empty() && st.stems.empty() && foliage.triangles.empty() && !background_) {
    throw InputError("ray scene: nothing to see (empty bunch and no background)");
  }
  st.device = rtcNewDevice("verbose=0");
  if (!st.device) throw InputError("ray scene: cannot create an Embree device");
  rtcSetDeviceErrorFunction(st.device, on_embree_error, &st.last_error);
  st.scene = rtcNewScene(st.device);
  rtcSetSceneBuildQuality(st.scene, RTC_BUILD_QUALITY_HIGH);

  if (!bunch.berries.empty()) {
    RTCGeometry g = rtcNewGeometry(st.device, RTC_GEOMETRY_TYPE_SPHERE_POINT);
    auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4,
                                                          4 * sizeof(float), bunch.berries.size()));
    for (std::size_t i = 0; i < bunch.berries.size(); ++i) {
      const Berry& b = bunch.berries[i];
      v[4 * i + 0] = static_cast<float>(b.centre.x());
      v[4 * i + 1] = static_cast<float>(b.centre.y());
      v[4 * i + 2] = static_cast<float>(b.centre.z());
      // A hair larger so float rounding never loses a grazing hit; refine() then
      // decides in double against the exact sphere.
      v[4 * i + 3] = static_cast<float>(b.radius * (1 + 1e-6));
    }
    rtcCommitGeometry(g);
    st.sphere_geom = rtcAttachGeometry(st.scene, g);
    rtcReleaseGeometry(g);
  }
  if (!st.stems.empty()) {
    RTCGeometry g = rtcNewGeometry(st.device, RTC_GEOMETRY_TYPE_USER);
    rtcSetGeometryUserPrimitiveCount(g, static_cast<unsigned>(st.stems.size()));
    rtcSetGeometryUserData(g, st.stems.data());
    rtcSetGeometryBoundsFunction(g, stem_bounds, nullptr);
    rtcSetGeometryIntersectFunction(g, stem_intersect);
    rtcSetGeometryOccludedFunction(g, stem_occluded);
    rtcCommitGeometry(g);
    st.stem_geom = rtcAttachGeometry(st.scene, g);
    rtcReleaseGeometry(g);
  }
  if (!foliage.triangles.empty()) {
    RTCGeometry g = rtcNewGeometry(st.device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                          3 * sizeof(float), foliage.vertices.size()));
    for (std::size_t i = 0; i < foliage.vertices.size(); ++i) {
      for (int a = 0; a < 3; ++a) v[3 * i + a] = static_cast<float>(foliage.vertices[i][a]);
    }
    auto* idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                               3 * sizeof(unsigned), foliage.triangles.size()));
    for (std::size_t i = 0; i < foliage.triangles.size(); ++i) {
      for (int a = 0; a < 3; ++a) idx[3 * i + a] = static_cast<unsigned>(foliage.triangles[i][a]);
    }
    rtcCommitGeometry(g);
    st.triangle_geom = rtcAttachGeometry(st.scene, g);
    rtcReleaseGeometry(g);
  }
  rtcCommitScene(st.scene);
  if (!st.last_error.empty()) throw InputError("ray scene: " + st.last_error);

  // The rigs aim at the bunch; the sensors trace every pixel that can see anything.
  Vec3 lo = Vec3::Constant(kInf), hi = Vec3::Constant(-kInf);
  const auto grow = [&](const Vec3& a, const Vec3& b, double r) {
    lo = lo.cwiseMin(a.cwiseMin(b) - Vec3::Constant(r));
    hi = hi.cwiseMax(a.cwiseMax(b) + Vec3::Constant(r));
  };
  for (const auto& b : bunch.berries) grow(b.centre, b.centre, b.radius);
  for (const auto& s : bunch.stems) grow(s.start, s.end, s.radius);
  const bool empty_bunch = bunch.berries.empty() && bunch.stems.empty();
  bunch_min_ = empty_bunch ? Vec3::Zero() : lo;
  bunch_max_ = empty_bunch ? Vec3::Zero() : hi;
  for (const auto& s : foliage.canes) grow(s.start, s.end, s.radius);
  for (const auto& v : foliage.vertices) grow(v, v, 0);
  if (lo.x() > hi.x()) lo = hi = Vec3::Zero();
  centre_ = 0.5 * (lo + hi);
  radius_ = 0.5 * (hi - lo).norm();
}

RayScene RayScene::with_background(std::optional<BackgroundPlane> background) const {
  RayScene r = *this;
  r.background_ = background;
  return r;
}

Hit RayScene::plane_hit(const Ray& ray) const {
  Hit h;
  if (!background_) return h;
  const double denom = background_->normal.dot(ray.direction);
  if (std::abs(denom) < 1e-12) return h;
  const double t = (background_->offset - background_->normal.dot(ray.origin)) / denom;
  if (t <= 0) return h;
  h.t = t;
  h.point = ray.origin + t * ray.direction;
  h.normal = denom < 0 ? background_->normal : Vec3(-background_->normal);
  h.cos_incidence = std::abs(denom);
  h.part = Part::Background;
  h.colour = background_->colour;
  return h;
}

void RayScene::refine(const Ray& ray, unsigned geom, unsigned prim, double t_float, Hit& h) const {
  if (geom == state_->sphere_geom) {
    const Berry& b = state_->bunch.berries[prim];
    const Vec3 oc = ray.origin - b.centre;
    const double bq = oc.dot(ray.direction), c = oc.squaredNorm() - b.radius * b.radius;
    const double disc = bq * bq - c;
    if (disc < 0) return;  // the float sphere was a hair larger: a true miss
    double t = -bq - std::sqrt(disc);
    if (t <= 0) t = t_float;
    h.t = t;
    h.point = ray.origin + t * ray.direction;
    h.normal = (h.point - b.centre) / b.radius;
    h.cos_incidence = std::max(0.0, -h.normal.dot(ray.direction));
    h.part = Part::Berry;
    h.berry = static_cast<int>(prim);
    h.primitive = static_cast<int>(prim);
    h.colour = b.colour;
    return;
  }
  if (geom == state_->triangle_geom) {
    // Exact in double against the triangle's plane.
    const auto& tri = state_->foliage.triangles[prim];
    const Vec3& a = state_->foliage.vertices[static_cast<std::size_t>(tri[0])];
    const Vec3 n = (state_->foliage.vertices[static_cast<std::size_t>(tri[1])] - a)
                       .cross(state_->foliage.vertices[static_cast<std::size_t>(tri[2])] - a)
                       .normalized();
    const double denom = n.dot(ray.direction);
    double t = std::abs(denom) > 1e-12 ? n.dot(a - ray.origin) / denom : t_float;
    if (!(t > 0)) t = t_float;
    h.t = t;
    h.point = ray.origin + t * ray.direction;
    h.normal = denom < 0 ? n : Vec3(-n);  // leaves are two-sided
    h.cos_incidence = std::abs(denom);
    h.part = Part::Leaf;
    h.berry = -1;
    h.primitive = static_cast<int>(prim);
    h.colour = state_->foliage.triangle_colour[prim];
    return;
  }
  const Stem& s = state_->stems[prim];
  double t;
  Vec3 n;
  if (!ray_cylinder(s, ray.origin, ray.direction, 0.0, t, n)) return;
  h.t = t;
  h.point = ray.origin + t * ray.direction;
  h.normal = n;
  h.cos_incidence = std::max(0.0, -n.dot(ray.direction));
  h.part = s.part;
  h.berry = s.berry;
  h.primitive = static_cast<int>(prim);
  h.colour = s.part == Part::Cane || s.part == Part::Background ? state_->foliage.colour_of(s) : state_->bunch.stem_colour;
}

void RayScene::set_miss(Hit& h) {
  // A miss sets only what says so: point, normal and colour are read only on hits.
  h.t = -1;
  h.part = Part::None;
  h.berry = h.primitive = -1;
}

void RayScene::resolve(const Ray& ray, const RTCRayHit16& rh, std::size_t k, double t_scale, bool plane, Hit& h) const {
  if (rh.hit.geomID[k] != RTC_INVALID_GEOMETRY_ID) refine(ray, rh.hit.geomID[k], rh.hit.primID[k], rh.ray.tfar[k] * t_scale, h);
  if (plane) {
    const Hit p = plane_hit(ray);
    if (p.valid() && (!h.valid() || p.t < h.t)) h = p;
  }
}

void RayScene::intersect(const std::vector<Ray>& rays, std::vector<Hit>& hits, bool bunch_only) const {
  hits.resize(rays.size());
  intersect(rays.data(), rays.size(), hits.data(), bunch_only);
}

void RayScene::intersect(const Ray* rays, std::size_t count, Hit* hits, bool bunch_only) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  alignas(64) RTCRayHit16 rh;
  alignas(64) int valid[16];
  for (std::size_t base = 0; base < count; base += 16) {
    const std::size_t n = std::min<std::size_t>(16, count - base);
    load_packet(rays + base, n, rh, valid);
    rtcIntersect16(valid, state_->scene, &context, &rh);
    for (std::size_t k = 0; k < n; ++k) {
      Hit& h = hits[base + k];
      set_miss(h);
      resolve(rays[base + k], rh, k, 1.0, !bunch_only && background_, h);
    }
  }
  if (!state_->last_error.empty()) throw InputError("ray scene: " + state_->last_error);
}

void RayScene::intersect_image_points(const PixelRays& camera, const double* uv, std::size_t count, Hit* hits,
                                      bool bunch_only) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  alignas(64) RTCRayHit16 rh;
  alignas(64) int valid[16];
  const bool plane = !bunch_only && background_.has_value();
  // Embree writes only tfar and the hit of a packet: the origin (the camera's), tnear,
  // time, mask, flags and id are set once; masked-off lanes keep finite directions.
  const Vec3& c2 = camera.c2;
  for (std::size_t k = 0; k < 16; ++k) {
    set_lane(rh, k, static_cast<float>(camera.origin.x()), static_cast<float>(camera.origin.y()),
             static_cast<float>(camera.origin.z()), static_cast<float>(c2.x()), static_cast<float>(c2.y()),
             static_cast<float>(c2.z()));
  }
  Vec3 dir[16];  // each lane's direction (length |d|), formed once per ray
  for (std::size_t base = 0; base < count; base += 16) {
    const std::size_t n = std::min<std::size_t>(16, count - base);
    for (std::size_t k = 0; k < n; ++k) {
      const std::size_t i = base + k;
      const Vec3 d = uv[2 * i] * camera.c0 + uv[2 * i + 1] * camera.c1 + c2;
      dir[k] = d;
      rh.ray.dir_x[k] = static_cast<float>(d.x());
      rh.ray.dir_y[k] = static_cast<float>(d.y());
      rh.ray.dir_z[k] = static_cast<float>(d.z());
      rh.ray.tfar[k] = INFINITY;
      rh.hit.geomID[k] = RTC_INVALID_GEOMETRY_ID;
      valid[k] = -1;
    }
    for (std::size_t k = n; k < 16; ++k) valid[k] = 0;
    rtcIntersect16(valid, state_->scene, &context, &rh);
    for (std::size_t k = 0; k < n; ++k) {
      Hit& h = hits[base + k];
      set_miss(h);
      if (rh.hit.geomID[k] == RTC_INVALID_GEOMETRY_ID && !plane) continue;
      const double len = std::sqrt(dir[k].squaredNorm());
      // Embree's t is in units of |d|.
      resolve({camera.origin, dir[k] * (1.0 / len)}, rh, k, len, plane, h);
    }
  }
  if (!state_->last_error.empty()) throw InputError("ray scene: " + state_->last_error);
}

Hit RayScene::intersect(const Ray& ray, bool bunch_only) const {
  std::vector<Hit> h;
  intersect(std::vector<Ray>{ray}, h, bunch_only);
  return h[0];
}

void RayScene::occluded(const std::vector<Vec3>& from, const std::vector<Vec3>& to, std::vector<char>& blocked) const {
  blocked.assign(from.size(), 0);
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  alignas(64) RTCRay16 ray;
  alignas(64) int valid[16];
  const double eps = 1e-5;  // m: the end points lie on surfaces
  for (std::size_t base = 0; base < from.size(); base += 16) {
    const std::size_t n = std::min<std::size_t>(16, from.size() - base);
    double len[16];
    Vec3 dir[16];
    for (std::size_t k = 0; k < 16; ++k) {
      const std::size_t i = base + std::min(k, n - 1);
      const Vec3 seg = to[i] - from[i];
      len[k] = seg.norm();
      dir[k] = len[k] > 0 ? Vec3(seg / len[k]) : Vec3::UnitZ();
      valid[k] = k < n && len[k] > 2 * eps ? -1 : 0;
      ray.org_x[k] = static_cast<float>(from[i].x());
      ray.org_y[k] = static_cast<float>(from[i].y());
      ray.org_z[k] = static_cast<float>(from[i].z());
      ray.dir_x[k] = static_cast<float>(dir[k].x());
      ray.dir_y[k] = static_cast<float>(dir[k].y());
      ray.dir_z[k] = static_cast<float>(dir[k].z());
      ray.tnear[k] = static_cast<float>(eps);
      ray.tfar[k] = static_cast<float>(len[k] - eps);
      ray.time[k] = 0;
      ray.mask[k] = 0xFFFFFFFFu;
      ray.flags[k] = 0;
      ray.id[k] = static_cast<unsigned>(k);
    }
    rtcOccluded16(valid, state_->scene, &context, &ray);
    for (std::size_t k = 0; k < n; ++k) {
      if (!valid[k]) continue;
      bool b = ray.tfar[k] == -INFINITY;
      if (!b && background_) {
        const Hit p = plane_hit({from[base + k], dir[k]});
        b = p.valid() && p.t > eps && p.t < len[k] - eps;
      }
      blocked[base + k] = b;
    }
  }
}

std::size_t RayScene::raw_intersect_count(const std::vector<Ray>& rays) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  alignas(64) RTCRayHit16 rh;
  alignas(64) int valid[16];
  std::size_t hits = 0;
  for (std::size_t base = 0; base < rays.size(); base += 16) {
    const std::size_t n = std::min<std::size_t>(16, rays.size() - base);
    load_packet(rays.data() + base, n, rh, valid);
    rtcIntersect16(valid, state_->scene, &context, &rh);
    for (std::size_t k = 0; k < n; ++k) hits += rh.hit.geomID[k] != RTC_INVALID_GEOMETRY_ID;
  }
  return hits;
}

}  // namespace grapebench
