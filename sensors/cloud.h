// One view of a scan: an organised point cloud with per-point ground truth.
#pragma once

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <memory>
#include <type_traits>
#include <vector>

#include "synth/types.h"

namespace grapebench {

// Storage of a frame's per-pixel arrays. Blocks of 64 KiB and more are recycled
// through a process-wide pool (bounded, thread-safe) instead of going back to the OS:
// a fresh block costs one page fault per 4 KiB on first write, which measured 35 % of
// an ideal 12-view turntable scan (perf, grapebench_sensor_perf).
void* frame_buffer_allocate(std::size_t bytes);
void frame_buffer_release(void* p, std::size_t bytes) noexcept;
// The same pool for blocks whose every byte equals `fill`. The releaser names the span
// [written_begin, written_end) it may have changed; only that span is refilled.
void* filled_buffer_allocate(std::size_t bytes, std::uint8_t fill);
void filled_buffer_release(void* p, std::size_t bytes, std::uint8_t fill, std::size_t written_begin,
                           std::size_t written_end) noexcept;

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

// A frame's per-pixel byte map (valid mask, part labels), n bytes, from the filled
// pool. A robot-pass frame sees the bunch in 3 % of its 848 x 480 pixels: clearing its
// two full maps for every frame was 5 % of the D435's capture time (perf,
// grapebench_sensor_perf). A writer that declares the span it writes (limit_writes)
// gets a recycled map that only had that span refilled. Scanning for the changed span
// instead measured 3.4 %: the maps do not stay in cache.
class ByteMap {
 public:
  ByteMap() = default;
  ByteMap(const ByteMap& o);
  ByteMap(ByteMap&& o) noexcept;
  ByteMap& operator=(ByteMap o) noexcept;
  ~ByteMap() { release(); }
  void assign(std::size_t n, std::uint8_t fill);  // n bytes, all `fill`; any may be written
  // Promise: only bytes in [begin, end) will change from `fill` (checked by
  // tests/sensors/artefacts_test.cpp for every sensor).
  void limit_writes(std::size_t begin, std::size_t end);
  std::size_t writes_begin() const { return begin_; }
  std::size_t writes_end() const { return end_; }
  std::size_t size() const { return n_; }
  std::uint8_t& operator[](std::size_t i) { return p_[i]; }
  std::uint8_t operator[](std::size_t i) const { return p_[i]; }
  const std::uint8_t* begin() const { return p_; }
  const std::uint8_t* end() const { return p_ + n_; }

 private:
  void release() noexcept;
  std::uint8_t* p_ = nullptr;
  std::size_t n_ = 0;
  std::size_t begin_ = 0, end_ = 0;  // the span that may differ from fill_
  std::uint8_t fill_ = 0;
};

struct OrganisedCloud {
  int width = 0, height = 0;
  // Per pixel, row-major (index = v * width + u).
  ByteMap valid;  // 1 when the sensor returns a point
  ByteMap label;  // Part of the surface seen (Part::None: nothing)
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
  std::vector<std::uint8_t> left_jpeg;  // the camera's JPEG file of left_image (jpeg_quality > 0), else empty
  double baseline = 0;          // m, left to right camera along +x (stereo sensors; 0 otherwise)
  std::uint64_t rays_cast = 0;  // rays traced for this frame (for rays-per-second figures)

  void resize(int w, int h);
  // Same, for a sensor that writes valid and label only in rows [first_row, end_row)
  // (clamped to the frame): recycled frames then need only those rows refilled.
  void resize(int w, int h, int first_row, int end_row);
  std::size_t size() const { return static_cast<std::size_t>(width) * height; }
  std::size_t valid_count() const;
  // Positions (sensor frame, m) of the valid returns on bunch parts (berry, pedicel,
  // rachis, peduncle): the ground-truth segmentation of the bunch.
  std::vector<Vec3> bunch_points() const;
};

}  // namespace grapebench
