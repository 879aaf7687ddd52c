// The ray-casting scene of one bunch: an Embree 3 device and scene owned by one RAII
// object (error callback set, no globals). Berries are Embree's native spheres, stems
// exact flat-capped cylinders through a user geometry (the same solids the ground
// truth measures); an optional background plane is intersected analytically, so
// rays that can only reach the plane never enter Embree.
#pragma once

#include <embree3/rtcore.h>

#include <cmath>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "synth/foliage.h"
#include "synth/types.h"

namespace grapebench {

// A plane n·x = offset (n unit, facing the cameras), infinite, of one colour.
struct BackgroundPlane {
  Vec3 normal = Vec3::UnitY();
  double offset = 0;
  Rgb colour{0.3f, 0.3f, 0.3f};
  double albedo = 0.5;
};

struct Hit {
  double t = -1;               // distance along the unit ray direction, m; < 0: miss
  Vec3 point = Vec3::Zero();   // m, world
  Vec3 normal = Vec3::Zero();  // unit, world, facing the ray
  Part part = Part::None;
  int berry = -1;      // berry id for berries and their pedicels, else -1
  int primitive = -1;  // berry or stem index; -1 for the plane
  Rgb colour;
  double cos_incidence = 0;  // cosine between the normal and the reversed ray, [0, 1]
  bool valid() const { return t >= 0; }
};

struct Ray {
  Vec3 origin;
  Vec3 direction;  // unit
};

// World rays through image points with the per-camera constants folded in once:
// d = u c0 + v c1 + c2 with c0 = R e_x / fx, c1 = R e_y / fy, c2 = R e_z - cx c0 - cy c1,
// then one square root and one division per ray (the sensors' inner loops).
struct PixelRays {
  Vec3 origin, c0, c1, c2;
  Ray operator()(double u, double v) const {
    const Vec3 d = u * c0 + v * c1 + c2;
    return {origin, d * (1.0 / std::sqrt(d.squaredNorm()))};
  }
};

// Entry distance t (m along the unit direction d) of the ray from o into the exact
// flat-capped cylinder of `s`, with the outward normal there; false when it misses it
// beyond tnear. The test every stem hit is refined by (and the datasets' amodal masks).
bool ray_cylinder(const Stem& s, const Vec3& o, const Vec3& d, double tnear, double& t, Vec3& normal);

class RayScene {
 public:
  // `foliage` (leaves as triangles, canes as exact cylinders) only occludes and
  // returns Leaf / Cane hits.
  explicit RayScene(const Bunch& bunch, std::optional<BackgroundPlane> background = std::nullopt,
                    const Foliage& foliage = Foliage{});
  // The same Embree scene (shared, not rebuilt) with another background.
  RayScene with_background(std::optional<BackgroundPlane> background) const;

  // Nearest hits of rays (any count), through 16-ray packets; hits are refined in
  // double precision against the exact primitive. `bunch_only` skips the plane.
  void intersect(const std::vector<Ray>& rays, std::vector<Hit>& hits, bool bunch_only = false) const;
  void intersect(const Ray* rays, std::size_t count, Hit* hits, bool bunch_only = false) const;
  Hit intersect(const Ray& ray, bool bunch_only = false) const;
  // The same for the camera rays through image points uv (count x 2, pixels): packets
  // are filled straight from the points with unnormalised float directions (Embree
  // needs no unit vector) and the unit double ray is formed only where it is needed
  // (hits, and every ray when a background plane is set). The sensors' hot path.
  void intersect_image_points(const PixelRays& camera, const double* uv, std::size_t count, Hit* hits,
                              bool bunch_only = false) const;
  // Whether anything (bunch or plane) blocks the segment from `from` to `to`,
  // excluding a tolerance at both ends. One packet per 16 queries.
  void occluded(const std::vector<Vec3>& from, const std::vector<Vec3>& to, std::vector<char>& blocked) const;

  // The background plane alone (analytic); a miss when there is none.
  Hit background_hit(const Ray& ray) const { return plane_hit(ray); }
  // Whether Embree holds anything (bunch or foliage): else only the plane can be hit.
  bool has_bunch() const {
    return !state_->bunch.berries.empty() || !state_->stems.empty() || !state_->foliage.triangles.empty();
  }

  // Raw Embree cast of the same packets with no refinement or labels: the
  // reference loop the sensor models are benchmarked against.
  std::size_t raw_intersect_count(const std::vector<Ray>& rays) const;

  const Bunch& bunch() const { return state_->bunch; }
  const Foliage& foliage() const { return state_->foliage; }
  const std::optional<BackgroundPlane>& background() const { return background_; }
  // Bounding sphere of everything Embree holds (bunch and foliage), m: the pixels the
  // sensors trace.
  Vec3 bounds_centre() const { return centre_; }
  double bounds_radius() const { return radius_; }
  // Bounding sphere of the bunch alone, m: what the rigs aim at.
  Vec3 bunch_centre() const { return 0.5 * (bunch_min_ + bunch_max_); }
  double bunch_radius() const { return 0.5 * (bunch_max_ - bunch_min_).norm(); }
  // Axis-aligned box of the bunch's berries and stems, m (both zero for an empty bunch).
  const Vec3& bunch_min() const { return bunch_min_; }
  const Vec3& bunch_max() const { return bunch_max_; }

 private:
  void refine(const Ray& ray, unsigned geom, unsigned prim, double t, Hit& hit) const;
  static void set_miss(Hit& hit);
  // Lane k of a cast packet into `hit` (preset to a miss): the refined bunch hit (Embree's
  // t times t_scale is the distance along the unit `ray`), or the plane when nearer.
  void resolve(const Ray& ray, const RTCRayHit16& rh, std::size_t k, double t_scale, bool plane, Hit& hit) const;
  Hit plane_hit(const Ray& ray) const;

  // The Embree device and scene with everything they point to; released together.
  struct State {
    Bunch bunch;
    Foliage foliage;
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;
    unsigned sphere_geom = RTC_INVALID_GEOMETRY_ID, stem_geom = RTC_INVALID_GEOMETRY_ID,
             triangle_geom = RTC_INVALID_GEOMETRY_ID;
    std::vector<Stem> stems;  // user data of the stem geometry: the bunch's, then the canes
    std::string last_error;   // written by Embree's error callback
    ~State();
  };
  RayScene() = default;

  std::shared_ptr<State> state_;
  std::optional<BackgroundPlane> background_;
  Vec3 centre_ = Vec3::Zero(), bunch_min_ = Vec3::Zero(), bunch_max_ = Vec3::Zero();
  double radius_ = 0;
};

}  // namespace grapebench
