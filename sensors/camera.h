// Pinhole cameras. Camera frame (OpenCV): x right, y down, z forward; pixel (u, v)
// has its centre at (u + 0.5, v + 0.5).
#pragma once

#include "sensors/ray_scene.h"

#include <cmath>

#include <Eigen/Geometry>

namespace grapebench {

struct Intrinsics {
  int width = 0, height = 0;  // pixels
  double fx = 0, fy = 0;      // pixels
  double cx = 0, cy = 0;      // pixels, this file's convention: pixel (u, v) spans [u, u + 1)
  // OpenCV's and Open3D's principal point (the centre of pixel (u, v) is at (u, v)):
  // what every exported file and every estimator input carries.
  double opencv_cx() const { return cx - 0.5; }
  double opencv_cy() const { return cy - 0.5; }
};

// Square pixels, principal point at the centre, from the horizontal field of view.
Intrinsics intrinsics_from_hfov(int width, int height, double hfov_deg);
// From the horizontal and vertical fields of view (non-square pixels allowed).
Intrinsics intrinsics_from_fov(int width, int height, double hfov_deg, double vfov_deg);

struct Camera {
  Intrinsics K;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  // camera to world

  Vec3 centre() const { return pose.translation(); }
  PixelRays pixel_rays() const {
    const auto R = pose.linear();
    const Vec3 c0 = R.col(0) / K.fx, c1 = R.col(1) / K.fy;
    return {pose.translation(), c0, c1, Vec3(R.col(2) - K.cx * c0 - K.cy * c1)};
  }
  // World ray through image point (u, v) in pixels; in loops, hoist pixel_rays().
  Ray ray(double u, double v) const { return pixel_rays()(u, v); }
  Vec3 to_camera(const Vec3& world) const { return pose.inverse() * world; }
  // Pixel rectangle [u0, u1) x [v0, v1) that contains the image of a ball; false when
  // the ball is behind the camera or off the image.
  bool ball_pixels(const Vec3& centre, double radius, int& u0, int& v0, int& u1, int& v1) const;
  // The same for a centre already in the camera frame (m): for many balls of one view.
  bool ball_pixels_camera_frame(const Vec3& centre, double radius, int& u0, int& v0, int& u1, int& v1) const;
};

// Camera at `eye` looking at `target`; `up` fixes the roll (image up = -y).
Eigen::Isometry3d look_at(const Vec3& eye, const Vec3& target, const Vec3& up = Vec3::UnitZ());

}  // namespace grapebench
