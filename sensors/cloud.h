// One view of a scan: an organised point cloud with per-point ground truth.
#pragma once

#include "synth/types.h"

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <memory>
#include <type_traits>
#include <vector>

namespace grapebench {

// Storage of a frame's per-pixel arrays. Blocks of 64 KiB and more are recycled
// through a process-wide pool (bounded, thread-safe) instead of going back to the OS:
// a fresh block costs one page fault per 4 KiB on first write, which measured 35 % of
// an ideal 12-view turntable scan (perf, grapebench_sensor_perf).
void* frame_buffer_allocate(std::size_t bytes);
void frame_buffer_release(void* p, std::size_t bytes) noexcept;

// Allocator that default-initialises (leaves trivial values unset) and draws from the
// frame pool: a frame's bulky arrays are only written where a ray returned, so
// zero-filling them first would cost as much as the ray casting (measured: 23 ms for
// 12 Kinect frames). Readers must check `valid` / `label` before reading them.
template <class T>
struct uninitialised_allocator {
  using value_type = T;
  uninitialised_allocator() = default;
  template <class U>
  uninitialised_allocator(const uninitialised_allocator<U>&) noexcept {}
  T* allocate(std::size_t n) { return static_cast<T*>(frame_buffer_allocate(n * sizeof(T))); }
  void deallocate(T* p, std::size_t n) noexcept { frame_buffer_release(p, n * sizeof(T)); }
  template <class U>
  void construct(U* p) noexcept(std::is_nothrow_default_constructible_v<U>) {
    ::new (static_cast<void*>(p)) U;
  }
  template <class U, class... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
  template <class U>
  bool operator==(const uninitialised_allocator<U>&) const noexcept {
    return true;
  }
};
template <class T>
using raw_vector = std::vector<T, uninitialised_allocator<T>>;

struct OrganisedCloud {
  int width = 0, height = 0;
  // Per pixel, row-major (index = v * width + u).
  raw_vector<std::uint8_t> valid;   // 1 when the sensor returns a point
  raw_vector<std::uint8_t> label;   // Part of the surface seen (Part::None: nothing)
  // Set only where label != None: berry id (berries and their pedicels), else -1.
  raw_vector<std::int32_t> berry;
  // Set only where valid: position and normal in the sensor frame (x right, y down,
  // z forward), metres, and colour.
  raw_vector<Eigen::Vector3f> xyz;
  raw_vector<Eigen::Vector3f> normal;
  raw_vector<std::array<std::uint8_t, 3>> rgb;
  // Set only where label != None: depth (z, m) of the surface the pixel sees, without
  // noise or mixing, for scoring and for tests of the sensor artefacts.
  raw_vector<float> true_depth;
  float truth(std::size_t i) const { return label[i] == static_cast<std::uint8_t>(Part::None) ? 0.0f : true_depth[i]; }
  // Rendered colour images of a stereo sensor (W x H x 3, row-major, top row first);
  // empty for depth sensors.
  std::vector<std::uint8_t> left_image, right_image;
  std::uint64_t rays_cast = 0;  // rays traced for this frame (for rays-per-second figures)

  void resize(int w, int h);
  std::size_t size() const { return static_cast<std::size_t>(width) * height; }
  std::size_t valid_count() const;
  // Positions (sensor frame, m) of the valid returns on bunch parts (berry, pedicel,
  // rachis, peduncle): the ground-truth segmentation of the bunch.
  std::vector<Vec3> bunch_points() const;
};

}  // namespace grapebench
