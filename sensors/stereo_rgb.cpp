#include "sensors/stereo_rgb.h"

#include <GL/gl.h>
#include <GL/osmesa.h>

#include <cmath>
#include <memory>

#include "sensors/ideal.h"
#include "sensors/render/ray_render.h"
#include "synth/temp_folder.h"
#include "synth/mesh.h"
#include "synth/rng.h"

namespace grapebench {

namespace {

// OSMesa context bound to an RGBA buffer; released on scope exit.
struct OffscreenContext {
  OSMesaContext ctx = nullptr;
  std::vector<unsigned char> buffer;
  OffscreenContext(int w, int h) : buffer(static_cast<std::size_t>(w) * h * 4) {
    ctx = OSMesaCreateContextExt(OSMESA_RGBA, 24, 0, 0, nullptr);
    if (!ctx) throw InputError("stereo_rgb: cannot create an OSMesa context");
    if (!OSMesaMakeCurrent(ctx, buffer.data(), GL_UNSIGNED_BYTE, w, h)) {
      OSMesaDestroyContext(ctx);
      throw InputError("stereo_rgb: cannot bind the OSMesa buffer");
    }
  }
  ~OffscreenContext() { OSMesaDestroyContext(ctx); }
  OffscreenContext(const OffscreenContext&) = delete;
  OffscreenContext& operator=(const OffscreenContext&) = delete;
};

// Vertex arrays of the visible bunch surface: positions, smooth normals, colours.
struct RenderMesh {
  std::vector<float> position, normal, colour;
  std::vector<unsigned> index;
};

RenderMesh render_mesh(const Bunch& bunch, int level) {
  MeshOptions o;
  o.sphere_subdivisions = level;
  o.tube_sides = 24;
  const TriMesh m = bunch_mesh(bunch, o);
  RenderMesh r;
  std::vector<Vec3> n(m.vertices.size(), Vec3::Zero());
  std::vector<Rgb> c(m.vertices.size(), bunch.stem_colour);
  for (std::size_t f = 0; f < m.faces.size(); ++f) {
    if (m.face_internal[f]) continue;
    const auto& t = m.faces[f];
    const Vec3 fn = (m.vertices[t[1]] - m.vertices[t[0]]).cross(m.vertices[t[2]] - m.vertices[t[0]]);
    for (int k : t) {
      n[k] += fn;  // area-weighted smooth normals (vertices are welded within a piece)
      if (m.face_part[f] == Part::Berry) c[k] = bunch.berries[m.face_berry[f]].colour;
    }
    for (int k : t) r.index.push_back(static_cast<unsigned>(k));
  }
  for (std::size_t v = 0; v < m.vertices.size(); ++v) {
    const Vec3 nn = n[v].squaredNorm() > 0 ? n[v].normalized() : Vec3::UnitZ();
    for (int k = 0; k < 3; ++k) {
      r.position.push_back(static_cast<float>(m.vertices[v][k]));
      r.normal.push_back(static_cast<float>(nn[k]));
    }
    r.colour.insert(r.colour.end(), {c[v].r, c[v].g, c[v].b});
  }
  return r;
}

// A leaf point's colour factor: 1 + amplitude * (a hashed value of its 3 mm cell, in
// [-1, 1]): the same on the surface in every view.
float leaf_shade(const Vec3& p, double amplitude) {
  const auto cell = [](double v) { return static_cast<std::uint64_t>(static_cast<std::int64_t>(std::floor(v / 0.003)) + (1 << 20)); };
  const std::uint64_t key = (cell(p.x()) * 73856093ULL) ^ (cell(p.y()) * 19349663ULL) ^ (cell(p.z()) * 83492791ULL);
  return static_cast<float>(1 + amplitude * (2 * hashed_uniform(0x1eaf7e47, key) - 1));
}

// The scene's foliage as the ray scene holds it: leaf triangles (flat, both faces lit;
// with a texture, each split into cells^2 with shaded vertices) and canes as 12-sided
// tubes with flat caps, one colour each.
RenderMesh foliage_mesh(const Foliage& f, double texture, int cells) {
  RenderMesh r;
  auto vertex = [&](const Vec3& p, const Vec3& n, const Rgb& c) {
    for (int k = 0; k < 3; ++k) {
      r.position.push_back(static_cast<float>(p[k]));
      r.normal.push_back(static_cast<float>(n[k]));
    }
    r.colour.insert(r.colour.end(), {c.r, c.g, c.b});
    r.index.push_back(static_cast<unsigned>(r.index.size()));
  };
  for (std::size_t t = 0; t < f.triangles.size(); ++t) {
    const auto& tri = f.triangles[t];
    const Vec3 &a = f.vertices[tri[0]], &b = f.vertices[tri[1]], &c = f.vertices[tri[2]];
    const Vec3 n = (b - a).cross(c - a).normalized();
    if (texture <= 0) {
      for (const Vec3* p : {&a, &b, &c}) vertex(*p, n, f.triangle_colour[t]);
      continue;
    }
    const Rgb base = f.triangle_colour[t];
    const auto at = [&](int i, int j) { return a + (b - a) * (static_cast<double>(i) / cells) + (c - a) * (static_cast<double>(j) / cells); };
    const auto shaded = [&](const Vec3& p) {
      const float s = leaf_shade(p, texture);
      vertex(p, n, Rgb{std::min(1.0f, base.r * s), std::min(1.0f, base.g * s), std::min(1.0f, base.b * s)});
    };
    for (int i = 0; i < cells; ++i) {
      for (int j = 0; i + j < cells; ++j) {
        shaded(at(i, j)), shaded(at(i + 1, j)), shaded(at(i, j + 1));
        if (i + j + 1 < cells) shaded(at(i + 1, j)), shaded(at(i + 1, j + 1)), shaded(at(i, j + 1));
      }
    }
  }
  constexpr int sides = 12;
  for (const Stem& s : f.canes) {
    const Vec3 d = (s.end - s.start).normalized();
    const Vec3 e1 = d.unitOrthogonal(), e2 = d.cross(e1);
    for (int k = 0; k < sides; ++k) {
      const double a0 = 2 * M_PI * k / sides, a1 = 2 * M_PI * (k + 1) / sides;
      const Vec3 n0 = std::cos(a0) * e1 + std::sin(a0) * e2, n1 = std::cos(a1) * e1 + std::sin(a1) * e2;
      const Vec3 p00 = s.start + s.radius * n0, p01 = s.start + s.radius * n1;
      const Vec3 p10 = s.end + s.radius * n0, p11 = s.end + s.radius * n1;
      const Rgb& c = f.colour_of(s);
      vertex(p00, n0, c), vertex(p10, n0, c), vertex(p11, n1, c);
      vertex(p00, n0, c), vertex(p11, n1, c), vertex(p01, n1, c);
      vertex(s.start, -d, c), vertex(p01, -d, c), vertex(p00, -d, c);
      vertex(s.end, d, c), vertex(p10, d, c), vertex(p11, d, c);
    }
  }
  return r;
}

// Procedural foliage: overlapping leaf-green blobs, deterministic in `seed`.
std::vector<unsigned char> foliage_texture(int size, std::uint64_t seed) {
  std::vector<float> img(static_cast<std::size_t>(size) * size * 3, 0.0f);
  for (int i = 0; i < size * size; ++i) {
    img[3 * i] = 0.10f;
    img[3 * i + 1] = 0.22f;
    img[3 * i + 2] = 0.08f;
  }
  Rng rng(seed);
  for (int b = 0; b < 220; ++b) {
    const double cx = rng.uniform(0, size), cy = rng.uniform(0, size), r = rng.uniform(6, 28);
    const double shade = rng.uniform(0.6, 1.3);
    const float col[3] = {static_cast<float>(0.16 * shade), static_cast<float>(0.38 * shade),
                          static_cast<float>(0.10 * shade)};
    for (int y = static_cast<int>(cy - r); y <= cy + r; ++y)
      for (int x = static_cast<int>(cx - r); x <= cx + r; ++x) {
        const double dx = x - cx, dy = (y - cy) * 1.6;  // leaf-like ellipses
        if (dx * dx + dy * dy > r * r) continue;
        const int xx = (x % size + size) % size, yy = (y % size + size) % size;
        for (int k = 0; k < 3; ++k) img[3 * (yy * size + xx) + k] = col[k];
      }
  }
  std::vector<unsigned char> out(img.size());
  for (std::size_t i = 0; i < img.size(); ++i)
    out[i] = static_cast<unsigned char>(std::lround(std::clamp(img[i], 0.0f, 1.0f) * 255));
  return out;
}

}  // namespace

Intrinsics StereoRgb::intrinsics() const {
  Intrinsics k;
  k.width = p_.width;
  k.height = p_.height;
  k.fx = k.fy = p_.focal_length_mm * 1e-3 / (p_.pixel_pitch_um * 1e-6);
  k.cx = 0.5 * p_.width;
  k.cy = 0.5 * p_.height;
  return k;
}

namespace {

// The pair's cameras: the left at `pose`, the right `baseline` along its x axis.
std::pair<Camera, Camera> stereo_cameras(const Intrinsics& k, const Eigen::Isometry3d& pose, double baseline) {
  Eigen::Isometry3d right_pose = pose;
  right_pose.translation() = pose * Vec3(baseline, 0, 0);
  return {Camera{k, pose}, Camera{k, right_pose}};
}

// The renderers' draws: the scene's, or redrawn with noise_seed.
std::uint64_t photo_seed(const StereoRgbParams& p, std::uint64_t seed) {
  return p.noise_seed != 0 ? derive_seed(seed, 0x5eed0000ull + static_cast<std::uint64_t>(p.noise_seed)) : seed;
}

// The exact frame `out` with the pair developed from linear images `l` and `r` (r
// empty without a right image); `seed` as photo_seed gives it.
void develop_pair(OrganisedCloud& out, const StereoRgbParams& p, const Camera& left, const Camera& right,
                  const std::vector<float>& l, const std::vector<float>& r, std::uint64_t seed) {
  // A synchronised pair: the right camera takes the left's exposure.
  const DevelopResult dl = develop_image(l, left.K, p.camera, derive_seed(seed, 2));
  out.baseline = p.baseline;
  out.left_image = dl.rgb;
  out.left_jpeg = dl.jpeg;
  if (p.right_image) out.right_image = develop_image(r, right.K, p.camera, derive_seed(seed, 3), dl.gain).rgb;
  for (std::size_t i = 0; i < out.size(); ++i) {
    if (out.valid[i]) out.rgb[i] = {out.left_image[3 * i], out.left_image[3 * i + 1], out.left_image[3 * i + 2]};
  }
}

// The keys of the light, left out of together_key.
constexpr const char* kLightKeys[] = {"light", "sun_elevation_deg", "sun_azimuth_deg", "sun", "ambient", "backdrop", "sun_size_deg"};

}  // namespace

OrganisedCloud StereoRgb::capture(const RayScene& scene, const Eigen::Isometry3d& pose, std::uint64_t seed) const {
  if (p_.renderer == StereoRgbParams::Renderer::Ray) {
    const Sensor* self = this;
    return std::move(capture_together(std::span<const Sensor* const>(&self, 1), scene, pose, seed)[0]);
  }
  const auto [left, right] = stereo_cameras(intrinsics(), pose, p_.baseline);
  OrganisedCloud out = capture_exact(scene, left);
  if (p_.renderer == StereoRgbParams::Renderer::Cycles) {
    const Illumination light = stereo_rgb_illumination(p_, pose);
    const double f = p_.focal_length_mm * 1e-3;
    seed = photo_seed(p_, seed);
    std::vector<float> l, r;
    const TempFolder work("grapebench-cycles");
    l = cycles_render(scene, left, light, p_.appearance, p_.camera, f, p_.cycles, derive_seed(seed, 4), work.path / "left").linear;
    if (p_.right_image) r = cycles_render(scene, right, light, p_.appearance, p_.camera, f, p_.cycles, derive_seed(seed, 5), work.path / "right").linear;
    develop_pair(out, p_, left, right, l, r, seed);
    return out;
  }

  const RenderMesh mesh = render_mesh(scene.bunch(), p_.mesh_level);
  const RenderMesh leaves = foliage_mesh(scene.foliage(), p_.leaf_texture, p_.texture_cells);
  const int W = p_.width, H = p_.height;
  const std::vector<unsigned char> texture = foliage_texture(256, derive_seed(seed, 1));
  // A background square behind the bunch, facing the left camera.
  const Vec3 view = pose.linear().col(2);
  const Vec3 centre = scene.bounds_centre() + p_.background_distance * view;
  const Vec3 bx = pose.linear().col(0), by = pose.linear().col(1);
  const double half = 3.0;  // m: fills any view of this rig

  OffscreenContext gl(W, H);
  const bool lamp = p_.light == StereoRgbParams::Light::Lamp;
  const SunLight sun = sun_light(p_);
  // From the scene towards the sun: azimuth about the vertical from "behind the camera".
  const Vec3 back = Vec3(-view.x(), -view.y(), 0).normalized();
  const double az = sun.azimuth_deg * M_PI / 180, el = sun.elevation_deg * M_PI / 180;
  const Vec3 sun_dir = std::cos(el) * (Eigen::AngleAxisd(az, Vec3::UnitZ()) * back) + std::sin(el) * Vec3::UnitZ();
  // One OpenGL image of a camera (RGB, top row first, 0-255), with or without the sun.
  auto draw = [&](const Camera& cam, bool with_sun, std::vector<float>& image) {
    const float backdrop = static_cast<float>(lamp ? 1.0 : std::min(1.0, sun.backdrop));
    const double n = 0.05, f = 20.0;
    glViewport(0, 0, W, H);
    glClearColor(0, 0, 0, 1);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glMatrixMode(GL_PROJECTION);
    glLoadIdentity();
    // OpenCV intrinsics as a frustum; OpenGL's y points up, so top uses cy.
    glFrustum(-cam.K.cx * n / cam.K.fx, (W - cam.K.cx) * n / cam.K.fx, -(H - cam.K.cy) * n / cam.K.fy,
              cam.K.cy * n / cam.K.fy, n, f);
    glMatrixMode(GL_MODELVIEW);
    glLoadIdentity();
    const GLfloat spec[4] = {static_cast<GLfloat>(p_.specular), static_cast<GLfloat>(p_.specular),
                             static_cast<GLfloat>(p_.specular), 1};
    // World to OpenGL eye: OpenCV camera frame with y and z flipped.
    Eigen::Matrix4d M = Eigen::Matrix4d::Identity();
    M(1, 1) = -1;
    M(2, 2) = -1;
    const Eigen::Matrix4d view_m = M * cam.pose.inverse().matrix();
    if (lamp) {
      const GLfloat light_pos[4] = {0.2f, 0.5f, 0.0f, 1.0f};  // eye frame: near the camera, a little above
      const GLfloat white[4] = {1, 1, 1, 1}, dim[4] = {0.25f, 0.25f, 0.25f, 1};
      glLightfv(GL_LIGHT0, GL_POSITION, light_pos);
      glLightfv(GL_LIGHT0, GL_DIFFUSE, white);
      glLightfv(GL_LIGHT0, GL_SPECULAR, white);
      glLightModelfv(GL_LIGHT_MODEL_AMBIENT, dim);
    }
    glLoadMatrixd(view_m.data());  // column-major, as OpenGL wants
    if (!lamp) {
      // The sun: directional, in world coordinates (so set after the view matrix).
      const auto k = static_cast<GLfloat>(with_sun ? sun.sun : 0.0), a = static_cast<GLfloat>(sun.ambient);
      const GLfloat dir[4] = {static_cast<GLfloat>(sun_dir.x()), static_cast<GLfloat>(sun_dir.y()),
                              static_cast<GLfloat>(sun_dir.z()), 0.0f};
      const GLfloat diffuse[4] = {k, k, k, 1}, ambient[4] = {a, a, a, 1};
      glLightfv(GL_LIGHT0, GL_POSITION, dir);
      glLightfv(GL_LIGHT0, GL_DIFFUSE, diffuse);
      glLightfv(GL_LIGHT0, GL_SPECULAR, diffuse);
      glLightModelfv(GL_LIGHT_MODEL_AMBIENT, ambient);
    }
    glEnable(GL_DEPTH_TEST);

    // Background.
    glDisable(GL_LIGHTING);
    GLuint tex = 0;
    if (p_.background == StereoRgbParams::Background::Foliage) {
      glGenTextures(1, &tex);
      glBindTexture(GL_TEXTURE_2D, tex);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
      glTexImage2D(GL_TEXTURE_2D, 0, GL_RGB, 256, 256, 0, GL_RGB, GL_UNSIGNED_BYTE, texture.data());
      glEnable(GL_TEXTURE_2D);
      glColor3f(backdrop, backdrop, backdrop);
    } else {
      glColor3f(backdrop * p_.plain_colour.r, backdrop * p_.plain_colour.g, backdrop * p_.plain_colour.b);
    }
    glBegin(GL_QUADS);
    const double reps = 8;
    const Vec3 corners[4] = {centre - half * bx - half * by, centre + half * bx - half * by,
                             centre + half * bx + half * by, centre - half * bx + half * by};
    const double uv[4][2] = {{0, 0}, {reps, 0}, {reps, reps}, {0, reps}};
    for (int k = 0; k < 4; ++k) {
      glTexCoord2d(uv[k][0], uv[k][1]);
      glVertex3d(corners[k].x(), corners[k].y(), corners[k].z());
    }
    glEnd();
    glDisable(GL_TEXTURE_2D);
    if (tex) glDeleteTextures(1, &tex);

    // Bunch: smooth Phong-lit surface, colours per vertex, specular highlights.
    glEnable(GL_LIGHTING);
    glEnable(GL_LIGHT0);
    glEnable(GL_NORMALIZE);
    glShadeModel(GL_SMOOTH);
    glEnable(GL_COLOR_MATERIAL);
    glColorMaterial(GL_FRONT_AND_BACK, GL_AMBIENT_AND_DIFFUSE);
    glMaterialfv(GL_FRONT_AND_BACK, GL_SPECULAR, spec);
    glMaterialf(GL_FRONT_AND_BACK, GL_SHININESS, static_cast<GLfloat>(p_.shininess));
    glEnableClientState(GL_VERTEX_ARRAY);
    glEnableClientState(GL_NORMAL_ARRAY);
    glEnableClientState(GL_COLOR_ARRAY);
    for (const RenderMesh* m : {&mesh, &leaves}) {
      if (m->index.empty()) continue;
      // Leaves are thin sheets: both faces lit (two-sided lighting), no highlights.
      glLightModeli(GL_LIGHT_MODEL_TWO_SIDE, m == &leaves ? GL_TRUE : GL_FALSE);
      const GLfloat none[4] = {0, 0, 0, 1};
      glMaterialfv(GL_FRONT_AND_BACK, GL_SPECULAR, m == &leaves ? none : spec);
      glVertexPointer(3, GL_FLOAT, 0, m->position.data());
      glNormalPointer(GL_FLOAT, 0, m->normal.data());
      glColorPointer(3, GL_FLOAT, 0, m->colour.data());
      glDrawElements(GL_TRIANGLES, static_cast<GLsizei>(m->index.size()), GL_UNSIGNED_INT, m->index.data());
    }
    glDisableClientState(GL_VERTEX_ARRAY);
    glDisableClientState(GL_NORMAL_ARRAY);
    glDisableClientState(GL_COLOR_ARRAY);
    glFinish();
    if (glGetError() != GL_NO_ERROR) throw InputError("stereo_rgb: OpenGL error while rendering");

    // OSMesa's row 0 is the bottom; images are stored top row first.
    image.resize(static_cast<std::size_t>(W) * H * 3);
    for (int y = 0; y < H; ++y) {
      const unsigned char* src = gl.buffer.data() + static_cast<std::size_t>(H - 1 - y) * W * 4;
      for (int x = 0; x < W; ++x) {
        for (int k = 0; k < 3; ++k) image[(static_cast<std::size_t>(y) * W + x) * 3 + k] = src[4 * x + k];
      }
    }
  };
  // Sun light reaches a pixel unless the exact scene blocks the way from its surface
  // point to the sun (the backdrop is not in the ray scene: always lit).
  auto sunlit = [&](const Camera& cam, const OrganisedCloud& exact) {
    std::vector<char> lit(exact.size(), 1);
    std::vector<Vec3> from, to;
    std::vector<std::size_t> pixel;
    for (std::size_t i = 0; i < exact.size(); ++i) {
      if (!exact.valid[i]) continue;
      const Vec3 world = cam.pose * exact.xyz[i].cast<double>();
      const Vec3 n = cam.pose.linear() * exact.normal[i].cast<double>();
      if (n.dot(sun_dir) <= 0) {
        lit[i] = 0;  // turned away from the sun
        continue;
      }
      from.push_back(world + 1e-4 * n);
      to.push_back(world + 20.0 * sun_dir);
      pixel.push_back(i);
    }
    std::vector<char> blocked;
    scene.occluded(from, to, blocked);
    for (std::size_t j = 0; j < pixel.size(); ++j) lit[pixel[j]] = !blocked[j];
    return lit;
  };
  // The camera's image: lamp-lit as drawn; sun-lit where the sun reaches, else the
  // ambient-only drawing; the backdrop scaled; exposure; sensor noise.
  auto render = [&](const Camera& cam, const OrganisedCloud& exact, std::vector<std::uint8_t>& image,
                    std::uint64_t noise_seed) {
    std::vector<float> full, shade;
    draw(cam, true, full);
    std::vector<char> lit;
    if (!lamp) {
      draw(cam, false, shade);
      lit = sunlit(cam, exact);
    }
    const double sd = 2.0 * p_.noise_scale;
    image.resize(full.size());
    for (std::size_t i = 0; i < full.size(); ++i) {
      double v = full[i];
      if (!lamp && exact.valid[i / 3] && !lit[i / 3]) v = shade[i];
      if (!lamp && !exact.valid[i / 3]) v *= std::max(1.0, sun.backdrop);  // backlit leaves above white
      v = p_.exposure * v + sd * hashed_normal(noise_seed, i);
      image[i] = static_cast<std::uint8_t>(std::clamp(std::lround(v), 0L, 255L));
    }
  };
  out.baseline = p_.baseline;
  render(left, out, out.left_image, derive_seed(seed, 2));
  if (p_.right_image) {
    const OrganisedCloud right_exact = lamp ? OrganisedCloud{} : capture_exact(scene, right);
    render(right, right_exact, out.right_image, derive_seed(seed, 3));
  }
  // The cloud's colours are the left image's.
  for (std::size_t i = 0; i < out.size(); ++i) {
    if (out.valid[i]) out.rgb[i] = {out.left_image[3 * i], out.left_image[3 * i + 1], out.left_image[3 * i + 2]};
  }
  return out;
}

nlohmann::ordered_json StereoRgb::describe() const { return with_type(type(), stereo_rgb_param_table().to_json(p_)); }

std::string StereoRgb::together_key() const {
  if (p_.renderer != StereoRgbParams::Renderer::Ray) return {};
  nlohmann::ordered_json j = describe();
  for (const char* k : kLightKeys) j.erase(k);
  return j.dump();
}

std::vector<OrganisedCloud> StereoRgb::capture_together(std::span<const Sensor* const> sensors, const RayScene& scene,
                                                        const Eigen::Isometry3d& pose, std::uint64_t seed) const {
  if (p_.renderer != StereoRgbParams::Renderer::Ray) return Sensor::capture_together(sensors, scene, pose, seed);
  const std::string key = together_key();
  std::vector<Illumination> lights;
  for (const Sensor* s : sensors) {
    const auto* rgb = dynamic_cast<const StereoRgb*>(s);
    if (rgb == nullptr || rgb->together_key() != key)
      throw std::logic_error("stereo_rgb: capture_together of sensors that differ in more than their light");
    lights.push_back(stereo_rgb_illumination(rgb->p_, pose));
  }
  const auto [left, right] = stereo_cameras(intrinsics(), pose, p_.baseline);
  const double f = p_.focal_length_mm * 1e-3;
  seed = photo_seed(p_, seed);
  const RayRenderScene rows = ray_render_scene(scene, p_.appearance);  // once for the pair
  const std::vector<RayRenderResult> l = ray_render(rows, left, lights, p_.appearance, p_.camera, f, derive_seed(seed, 4));
  std::vector<RayRenderResult> r(lights.size());  // empty images without a right camera
  if (p_.right_image) r = ray_render(rows, right, lights, p_.appearance, p_.camera, f, derive_seed(seed, 5));
  OrganisedCloud exact = capture_exact(scene, left);  // the labels' rays: the same under every light
  std::vector<OrganisedCloud> out;
  out.reserve(lights.size());
  for (std::size_t k = 0; k < lights.size(); ++k) {
    out.push_back(k + 1 < lights.size() ? exact : std::move(exact));
    develop_pair(out.back(), p_, left, right, l[k].linear, r[k].linear, seed);
  }
  return out;
}

Illumination stereo_rgb_illumination(const StereoRgbParams& p, const Eigen::Isometry3d& pose) {
  const SunLight sl = sun_light(p);
  const Vec3 view = pose.linear().col(2);
  const Vec3 back = Vec3(-view.x(), -view.y(), 0).normalized();
  const double az = sl.azimuth_deg * M_PI / 180, el = sl.elevation_deg * M_PI / 180;
  Illumination light;
  light.sun_direction = std::cos(el) * (Eigen::AngleAxisd(az, Vec3::UnitZ()) * back) + std::sin(el) * Vec3::UnitZ();
  // The presets' sun and ambient strengths read as the sun's irradiance and the sky's
  // on a horizontal surface; a sky brighter than its sun (overcast) is the CIE
  // overcast sky, else a clear one.
  light.sun = sl.sun;
  light.sky_irradiance = sl.ambient;
  light.sun_size_deg = p.sun_size_deg;
  light.sky = sl.sun < sl.ambient ? Illumination::Sky::Overcast : Illumination::Sky::Clear;
  return light;
}

SunLight sun_light(const StereoRgbParams& p) {
  using L = StereoRgbParams::Light;
  switch (p.light) {
    case L::Front:
      return {45, 25, 0.8, 0.25, 1.0};  // sun behind the camera, a little aside
    case L::Overshadow:
      return {35, 180, 0.9, 0.18, 1.3};  // sun behind the cluster: its front in shadow, leaves backlit
    case L::Overcast:
      return {60, 0, 0.1, 0.7, 0.8};  // sky light, hardly any sun
    case L::Lamp:
    case L::Custom:
      break;
  }
  return {p.sun_elevation_deg, p.sun_azimuth_deg, p.sun, p.ambient, p.backdrop};
}

const ParamTable<StereoRgbParams>& stereo_rgb_param_table() {
  using P = StereoRgbParams;
  const auto custom = [](const P& p) { return p.light == P::Light::Custom; };
  const auto ray = [](const P& p) { return p.renderer != P::Renderer::OpenGl; };
  static const ParamTable<P> table =
      ParamTable<P>()
          .integer("width", "px", &P::width, 64, 4096, "image width (seed 001: 800)")
          .integer("height", "px", &P::height, 64, 4096, "image height (seed 001: 600)")
          .real("focal_length_mm", "mm", &P::focal_length_mm, 1, 100, "lens focal length (seed 001: 6 mm)")
          .real("pixel_pitch_um", "um", &P::pixel_pitch_um, 1, 50,
                "pixel pitch (not stated in seed 001; 6 um: f = 1000 px)")
          .real("baseline", "m", &P::baseline, 0.01, 1, "left to right camera (seed 001: 5 cm)")
          .boolean("right_image", &P::right_image,
                   "render the right camera's image too (false: the left only, as `grapebench dataset` needs, "
                   "in half the time; protocol stereo_pair's estimators need the pair)")
          .choice("background", &P::background, {{"foliage", P::Background::Foliage}, {"plain", P::Background::Plain}},
                  "what the images show behind the bunch")
          .rgb("plain_colour", &P::plain_colour, "the plain background's colour")
          .when("background: plain", [](const P& p) { return p.background == P::Background::Plain; })
          .real("background_distance", "m", &P::background_distance, 0.05, 10, "background square behind the bunch")
          .real("specular", "-", &P::specular, 0, 1, "specular strength of berries")
          .real("shininess", "-", &P::shininess, 1, 128, "Phong exponent")
          .integer("mesh_level", "count", &P::mesh_level, 1, 5, "icosphere level of the rendered berries")
          .real("noise_scale", "-", &P::noise_scale, 0, 20, "image noise sd = 2/255 * noise_scale")
          .choice("light", &P::light,
                  {{"lamp", P::Light::Lamp},
                   {"front", P::Light::Front},
                   {"overshadow", P::Light::Overshadow},
                   {"overcast", P::Light::Overcast},
                   {"custom", P::Light::Custom}},
                  "lamp beside the camera; seed 001's sunny front light, sunny overshadow (sun behind the cluster) "
                  "and overcast; or custom (sensors/stereo_rgb.h lists what each preset sets)")
          .real("sun_elevation_deg", "deg", &P::sun_elevation_deg, -10, 90, "custom: sun above the horizon")
          .when("light: custom", custom)
          .real("sun_azimuth_deg", "deg", &P::sun_azimuth_deg, -180, 180,
                "custom: sun about the vertical, 0 behind the camera, 180 behind the cluster")
          .when("light: custom", custom)
          .real("sun", "-", &P::sun, 0, 2, "custom: the sun's diffuse and specular strength")
          .when("light: custom", custom)
          .real("ambient", "-", &P::ambient, 0, 2, "custom: the sky's ambient strength")
          .when("light: custom", custom)
          .real("backdrop", "-", &P::backdrop, 0, 3, "custom: brightness of the backdrop (backlit leaves above 1)")
          .when("light: custom", custom)
          .real("exposure", "-", &P::exposure, 0.1, 10, "gain on every pixel before the noise")
          .real("leaf_texture", "-", &P::leaf_texture, 0, 1,
                "relative colour variation fixed to the leaf surface, for matching (0: flat leaves)")
          .integer("texture_cells", "count", &P::texture_cells, 1, 32, "leaf triangles split into this many squared")
          .when("leaf_texture above 0", [](const P& p) { return p.leaf_texture > 0; })
          .choice("renderer", &P::renderer,
                  {{"opengl", P::Renderer::OpenGl}, {"ray", P::Renderer::Ray}, {"cycles", P::Renderer::Cycles}},
                  "opengl: OSMesa, Phong (every figure so far); ray: the appearance model, sun and sky, the camera "
                  "chain; cycles: the same scene path traced by Blender (the reference)")
          .real("sun_size_deg", "deg", &P::sun_size_deg, 0, 20, "ray: the sun's angular diameter (0.53: the solar disc)")
          .when("renderer: ray or cycles", ray)
          .integer("noise_seed", "-", &P::noise_seed, 0, 1000000,
                   "ray and cycles: 0 keeps the scene's draws; another value redraws the renderer's sampling and the "
                   "camera's noise, scene and truth unchanged (a figure's spread over the images' own noise)")
          .when("renderer: ray or cycles", ray)
          .section("appearance", &P::appearance, appearance_param_table(),
                   "ray: what berries, leaves, stems, ground and rows reflect (sensors/render/appearance.h)")
          .when("renderer: ray or cycles", ray)
          .section("camera", &P::camera, photo_camera_param_table(),
                   "ray: exposure, noise, Bayer, sRGB, lens and JPEG (sensors/render/develop_image.h)")
          .when("renderer: ray or cycles", ray)
          .section("cycles", &P::cycles, cycles_param_table(), "cycles: samples, threads, time limit, leaf atlas")
          .when("renderer: cycles", [](const P& p) { return p.renderer == P::Renderer::Cycles; })
          .validate([](const P& p, const ConfigNode& node) {
            if (p.renderer != P::Renderer::OpenGl && p.light == P::Light::Lamp)
              node.fail("light", "the ray and cycles renderers are lit by a sun and a sky: front, overshadow, overcast or custom "
                                 "(lamp is the OpenGL renderer's)");
          });
  return table;
}

}  // namespace grapebench
