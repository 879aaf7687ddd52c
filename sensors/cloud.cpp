#include "sensors/cloud.h"

#include <algorithm>
#include <cstring>
#include <stdexcept>
#include <mutex>
#include <new>
#include <utility>

namespace grapebench {

namespace {

constexpr std::size_t kPooledMin = std::size_t{64} << 10;  // bytes: smaller blocks go to malloc
constexpr std::size_t kPoolMax = std::size_t{512} << 20;   // bytes kept at most

#if defined(__SANITIZE_ADDRESS__)
constexpr bool kPooling = false;  // let ASan see every frame buffer's lifetime
#else
constexpr bool kPooling = true;
#endif

constexpr int kUnknown = -1;  // a pooled block's contents are unknown

struct FramePool {
  std::mutex mutex;
  struct Block {
    std::size_t bytes;
    int fill;  // the byte every position holds, or kUnknown
    void* p;
  };
  std::vector<Block> free;  // most recent last
  std::size_t kept = 0;
};

// Never destroyed: frames held by static objects may be released after main().
FramePool& pool() {
  static FramePool* p = new FramePool;
  return *p;
}

// A pooled block of `bytes`, preferring one filled with `fill` (kUnknown: any); sets
// `filled` when its contents are known to be all `fill`. Null when none is pooled.
void* take(std::size_t bytes, int fill, bool& filled) {
  filled = false;
  if (!kPooling || bytes < kPooledMin) return nullptr;
  FramePool& fp = pool();
  std::lock_guard lock(fp.mutex);
  std::size_t best = fp.free.size();
  for (std::size_t k = fp.free.size(); k-- > 0;) {
    if (fp.free[k].bytes != bytes) continue;
    if (best == fp.free.size() || (fill != kUnknown && fp.free[k].fill == fill)) best = k;
    if (fill == kUnknown || fp.free[k].fill == fill) break;
  }
  if (best == fp.free.size()) return nullptr;
  void* p = fp.free[best].p;
  filled = fill != kUnknown && fp.free[best].fill == fill;
  fp.free.erase(fp.free.begin() + static_cast<std::ptrdiff_t>(best));
  fp.kept -= bytes;
  return p;
}

void give(void* p, std::size_t bytes, int fill) noexcept {
  if (!p) return;
  if (kPooling && bytes >= kPooledMin) {
    FramePool& fp = pool();
    std::lock_guard lock(fp.mutex);
    if (fp.kept + bytes <= kPoolMax) {
      try {
        fp.free.push_back({bytes, fill, p});
        fp.kept += bytes;
        return;
      } catch (const std::bad_alloc&) {
      }
    }
  }
  ::operator delete(p);
}

}  // namespace

void* frame_buffer_allocate(std::size_t bytes) {
  bool filled;
  if (void* p = take(bytes, kUnknown, filled)) return p;
  return ::operator new(bytes);
}

void frame_buffer_release(void* p, std::size_t bytes) noexcept { give(p, bytes, kUnknown); }

void* filled_buffer_allocate(std::size_t bytes, std::uint8_t fill) {
  bool filled;
  void* p = take(bytes, fill, filled);
  if (!p) p = ::operator new(bytes);
  if (!filled) std::memset(p, fill, bytes);
  return p;
}

void filled_buffer_release(void* p, std::size_t bytes, std::uint8_t fill, std::size_t written_begin,
                           std::size_t written_end) noexcept {
  if (!p) return;
  if (!kPooling || bytes < kPooledMin) {
    ::operator delete(p);
    return;
  }
  std::memset(static_cast<std::uint8_t*>(p) + written_begin, fill, written_end - written_begin);
  give(p, bytes, fill);
}

ByteMap::ByteMap(const ByteMap& o) : n_(o.n_), end_(o.n_), fill_(o.fill_) {
  if (n_ == 0) return;
  p_ = static_cast<std::uint8_t*>(filled_buffer_allocate(n_, fill_));
  std::memcpy(p_, o.p_, n_);
}

ByteMap::ByteMap(ByteMap&& o) noexcept
    : p_(std::exchange(o.p_, nullptr)),
      n_(std::exchange(o.n_, 0)),
      begin_(std::exchange(o.begin_, 0)),
      end_(std::exchange(o.end_, 0)),
      fill_(o.fill_) {}

ByteMap& ByteMap::operator=(ByteMap o) noexcept {
  std::swap(p_, o.p_);
  std::swap(n_, o.n_);
  std::swap(begin_, o.begin_);
  std::swap(end_, o.end_);
  std::swap(fill_, o.fill_);
  return *this;
}

void ByteMap::assign(std::size_t n, std::uint8_t fill) {
  release();
  if (n == 0) return;
  p_ = static_cast<std::uint8_t*>(filled_buffer_allocate(n, fill));
  n_ = n;
  begin_ = 0;
  end_ = n;
  fill_ = fill;
}

void ByteMap::limit_writes(std::size_t begin, std::size_t end) {
  if (begin > end || end > n_) throw std::invalid_argument("ByteMap::limit_writes: span outside the map");
  begin_ = begin;
  end_ = end;
}

void ByteMap::release() noexcept {
  if (p_) filled_buffer_release(p_, n_, fill_, begin_, end_);
  p_ = nullptr;
  n_ = begin_ = end_ = 0;
}

void OrganisedCloud::resize(int w, int h) { resize(w, h, 0, h); }

void OrganisedCloud::resize(int w, int h, int first_row, int end_row) {
  width = w;
  height = h;
  const std::size_t n = size();
  valid.assign(n, 0);
  label.assign(n, static_cast<std::uint8_t>(Part::None));
  first_row = std::clamp(first_row, 0, h);
  end_row = std::clamp(end_row, first_row, h);
  const std::size_t b = static_cast<std::size_t>(first_row) * w, e = static_cast<std::size_t>(end_row) * w;
  valid.limit_writes(b, e);
  label.limit_writes(b, e);
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
