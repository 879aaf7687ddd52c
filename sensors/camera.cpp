#include "sensors/camera.h"

#include "synth/config.h"

#include <algorithm>
#include <cmath>

namespace grapebench {

Intrinsics intrinsics_from_hfov(int width, int height, double hfov_deg) {
  Intrinsics k;
  k.width = width;
  k.height = height;
  k.fx = k.fy = 0.5 * width / std::tan(0.5 * hfov_deg * M_PI / 180);
  k.cx = 0.5 * width;
  k.cy = 0.5 * height;
  return k;
}

Intrinsics intrinsics_from_fov(int width, int height, double hfov_deg, double vfov_deg) {
  Intrinsics k = intrinsics_from_hfov(width, height, hfov_deg);
  k.fy = 0.5 * height / std::tan(0.5 * vfov_deg * M_PI / 180);
  return k;
}

bool Camera::ball_pixels(const Vec3& c, double r, int& u0, int& v0, int& u1, int& v1) const {
  return ball_pixels_camera_frame(to_camera(c), r, u0, v0, u1, v1);
}

bool Camera::ball_pixels_camera_frame(const Vec3& p, double r, int& u0, int& v0, int& u1, int& v1) const {
  if (p.z() <= r) {  // the camera is inside or behind the ball's front: take all pixels
    if (p.z() + r <= 0) return false;
    u0 = v0 = 0;
    u1 = K.width;
    v1 = K.height;
    return true;
  }
  // Exact image extent: the planes x = m z through the centre of projection tangent
  // to the ball satisfy m^2 (z^2 - r^2) - 2 m x z + x^2 - r^2 = 0 (same for y).
  auto extent = [&](double x, double f, double c0, int n, int& lo, int& hi) {
    const double a = p.z() * p.z() - r * r;
    const double root = r * std::sqrt(std::max(0.0, x * x + a));
    const double mlo = (x * p.z() - root) / a, mhi = (x * p.z() + root) / a;
    lo = static_cast<int>(std::clamp(std::floor(c0 + f * mlo) - 1, 0.0, static_cast<double>(n)));
    hi = static_cast<int>(std::clamp(std::ceil(c0 + f * mhi) + 1, 0.0, static_cast<double>(n)));
  };
  extent(p.x(), K.fx, K.cx, K.width, u0, u1);
  extent(p.y(), K.fy, K.cy, K.height, v0, v1);
  return u0 < u1 && v0 < v1;
}

Eigen::Isometry3d look_at(const Vec3& eye, const Vec3& target, const Vec3& up) {
  const Vec3 z = (target - eye).normalized();
  Vec3 x = z.cross(up);
  if (x.squaredNorm() < 1e-12) x = z.cross(Vec3::UnitX());
  if (x.squaredNorm() < 1e-12) throw InputError("look_at: view direction parallel to up");
  x.normalize();
  const Vec3 y = z.cross(x);  // image down
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear().col(0) = x;
  T.linear().col(1) = y;
  T.linear().col(2) = z;
  T.translation() = eye;
  return T;
}

}  // namespace grapebench
