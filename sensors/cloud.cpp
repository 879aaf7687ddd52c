#include "sensors/cloud.h"

#include <mutex>
#include <new>

namespace grapebench {

namespace {

constexpr std::size_t kPooledMin = std::size_t{64} << 10;  // bytes: smaller blocks go to malloc
constexpr std::size_t kPoolMax = std::size_t{512} << 20;   // bytes kept at most

#if defined(__SANITIZE_ADDRESS__)
constexpr bool kPooling = false;  // let ASan see every frame buffer's lifetime
#else
constexpr bool kPooling = true;
#endif

struct FramePool {
  std::mutex mutex;
  std::vector<std::pair<std::size_t, void*>> free;  // (bytes, block), most recent last
  std::size_t kept = 0;
};

// Never destroyed: frames held by static objects may be released after main().
FramePool& pool() {
  static FramePool* p = new FramePool;
  return *p;
}

}  // namespace

void* frame_buffer_allocate(std::size_t bytes) {
  if (kPooling && bytes >= kPooledMin) {
    FramePool& fp = pool();
    std::lock_guard lock(fp.mutex);
    for (std::size_t k = fp.free.size(); k-- > 0;) {
      if (fp.free[k].first != bytes) continue;
      void* p = fp.free[k].second;
      fp.free.erase(fp.free.begin() + static_cast<std::ptrdiff_t>(k));
      fp.kept -= bytes;
      return p;
    }
  }
  return ::operator new(bytes);
}

void frame_buffer_release(void* p, std::size_t bytes) noexcept {
  if (!p) return;
  if (kPooling && bytes >= kPooledMin) {
    FramePool& fp = pool();
    std::lock_guard lock(fp.mutex);
    if (fp.kept + bytes <= kPoolMax) {
      try {
        fp.free.emplace_back(bytes, p);
        fp.kept += bytes;
        return;
      } catch (const std::bad_alloc&) {
      }
    }
  }
  ::operator delete(p);
}

void OrganisedCloud::resize(int w, int h) {
  width = w;
  height = h;
  const std::size_t n = size();
  valid.assign(n, 0);
  label.assign(n, static_cast<std::uint8_t>(Part::None));
  berry.resize(n);
  xyz.resize(n);
  normal.resize(n);
  rgb.resize(n);
  true_depth.resize(n);
}

std::size_t OrganisedCloud::valid_count() const {
  std::size_t n = 0;
  for (auto v : valid) n += v;
  return n;
}

std::vector<Vec3> OrganisedCloud::bunch_points() const {
  std::vector<Vec3> pts;
  for (std::size_t i = 0; i < size(); ++i) {
    if (valid[i] && label[i] <= static_cast<std::uint8_t>(Part::Peduncle)) pts.push_back(xyz[i].cast<double>());
  }
  return pts;
}

}  // namespace grapebench
