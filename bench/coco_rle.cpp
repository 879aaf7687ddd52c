#include "bench/coco_rle.h"

#include <algorithm>
#include <array>
#include <stdexcept>

namespace grapebench {

Rle rle_encode(const std::uint8_t* mask, int u0, int v0, int box_w, int box_h, int width, int height) {
  if (width < 0 || height < 0 || box_w < 0 || box_h < 0 || u0 < 0 || v0 < 0 || u0 + box_w > width || v0 + box_h > height)
    throw std::invalid_argument("rle_encode: the box is not inside the image");
  Rle r{height, width, {}};
  // Column-major position of the last change, and the value since.
  std::uint64_t last = 0;
  bool value = false;
  auto flip = [&](std::uint64_t at) {
    r.counts.push_back(static_cast<std::uint32_t>(at - last));
    last = at;
    value = !value;
  };
  const std::uint64_t h = static_cast<std::uint64_t>(height);
  for (int u = u0; u < u0 + box_w; ++u) {
    const std::uint64_t column = static_cast<std::uint64_t>(u) * h;
    for (int v = v0; v < v0 + box_h; ++v) {
      const bool on = mask[static_cast<std::size_t>(v - v0) * static_cast<std::size_t>(box_w) + (u - u0)] != 0;
      if (on != value) flip(column + static_cast<std::uint64_t>(v));
    }
    // Below the box the column is 0: a set run ends there.
    if (value && v0 + box_h < height) flip(column + static_cast<std::uint64_t>(v0 + box_h));
    // Above the box in the next column is 0 too.
    if (value && u + 1 < u0 + box_w && v0 > 0) flip(column + h);
  }
  const std::uint64_t total = static_cast<std::uint64_t>(width) * h;
  if (value) flip(static_cast<std::uint64_t>(u0 + box_w) * h);  // the column after the box starts with 0
  if (last < total || r.counts.empty()) r.counts.push_back(static_cast<std::uint32_t>(total - last));
  return r;
}

Rle rle_encode(const std::uint8_t* mask, int width, int height) { return rle_encode(mask, 0, 0, width, height, width, height); }

std::vector<std::uint8_t> rle_decode(const Rle& r) {
  std::vector<std::uint8_t> m(static_cast<std::size_t>(r.width) * static_cast<std::size_t>(r.height), 0);
  std::uint64_t at = 0;
  bool value = false;
  const std::uint64_t h = static_cast<std::uint64_t>(r.height);
  for (const std::uint32_t c : r.counts) {
    if (value) {
      for (std::uint64_t i = at; i < at + c && i < m.size(); ++i) {
        const std::uint64_t u = i / h, v = i % h;
        m[v * static_cast<std::uint64_t>(r.width) + u] = 1;
      }
    }
    at += c;
    value = !value;
  }
  return m;
}

std::string rle_string(const Rle& r) {
  // pycocotools' rleToString: the difference to the run two before from the fourth run
  // on (its `i > 2`; kept so the strings are byte-identical to pycocotools').
  std::string s;
  for (std::size_t i = 0; i < r.counts.size(); ++i) {
    long long x = r.counts[i];
    if (i > 2) x -= r.counts[i - 2];
    bool more = true;
    while (more) {
      char c = static_cast<char>(x & 0x1f);
      x >>= 5;
      more = (c & 0x10) ? x != -1 : x != 0;
      if (more) c |= 0x20;
      s.push_back(static_cast<char>(c + 48));
    }
  }
  return s;
}

Rle rle_from_string(const std::string& s, int height, int width) {
  if (height < 0 || width < 0) throw std::invalid_argument("negative mask size");
  Rle r{height, width, {}};
  std::size_t p = 0;
  std::uint64_t sum = 0;
  while (p < s.size()) {
    long long x = 0;
    int k = 0;
    bool more = true;
    while (more) {
      if (p >= s.size()) throw std::invalid_argument("the string ends inside a run");
      const int c = static_cast<unsigned char>(s[p]) - 48;
      if (c < 0 || c > 63) throw std::invalid_argument("character " + std::to_string(p) + " is outside '0'..'o'");
      if (k > 10) throw std::invalid_argument("run " + std::to_string(r.counts.size()) + " is too long");
      x |= static_cast<long long>(c & 0x1f) << (5 * k);
      more = (c & 0x20) != 0;
      ++p, ++k;
      if (!more && (c & 0x10)) x |= -1LL << (5 * k);
    }
    const std::size_t m = r.counts.size();
    if (m > 2) x += r.counts[m - 2];
    if (x < 0 || x > 0xffffffffLL) throw std::invalid_argument("run " + std::to_string(m) + " is negative or too long");
    r.counts.push_back(static_cast<std::uint32_t>(x));
    sum += static_cast<std::uint64_t>(x);
  }
  if (sum != static_cast<std::uint64_t>(height) * static_cast<std::uint64_t>(width))
    throw std::invalid_argument("the runs cover " + std::to_string(sum) + " pixels, the mask has " +
                                std::to_string(static_cast<std::uint64_t>(height) * width));
  return r;
}

std::uint64_t rle_area(const Rle& r) {
  std::uint64_t a = 0;
  for (std::size_t i = 1; i < r.counts.size(); i += 2) a += r.counts[i];
  return a;
}

std::array<double, 4> rle_box(const Rle& r) {
  if (r.height == 0) return {0, 0, 0, 0};
  const std::uint64_t h = static_cast<std::uint64_t>(r.height);
  std::uint64_t at = 0;
  std::uint64_t xs = UINT64_MAX, xe = 0, ys = UINT64_MAX, ye = 0;
  bool any = false;
  for (std::size_t i = 0; i < r.counts.size(); ++i) {
    const std::uint64_t c = r.counts[i];
    if (i % 2 == 1 && c > 0) {
      any = true;
      const std::uint64_t first = at, lastp = at + c - 1;
      const std::uint64_t u0 = first / h, u1 = lastp / h;
      xs = std::min(xs, u0), xe = std::max(xe, u1);
      if (u0 == u1) {
        ys = std::min(ys, first % h), ye = std::max(ye, lastp % h);
      } else {  // the run wraps into later columns: it covers a whole column's height
        ys = std::min(ys, std::uint64_t{0}), ye = std::max(ye, h - 1);
      }
    }
    at += c;
  }
  if (!any) return {0, 0, 0, 0};
  return {static_cast<double>(xs), static_cast<double>(ys), static_cast<double>(xe - xs + 1),
          static_cast<double>(ye - ys + 1)};
}

double rle_iou(const Rle& a, const Rle& b, bool crowd) {
  if (a.height != b.height || a.width != b.width) throw std::invalid_argument("rle_iou: masks of different sizes");
  // Walk both run lists together.
  std::uint64_t inter = 0;
  std::size_t i = 0, j = 0;
  std::uint64_t ca = a.counts.empty() ? 0 : a.counts[0], cb = b.counts.empty() ? 0 : b.counts[0];
  bool va = false, vb = false;
  while (i < a.counts.size() && j < b.counts.size()) {
    const std::uint64_t c = std::min(ca, cb);
    if (va && vb) inter += c;
    ca -= c, cb -= c;
    if (ca == 0 && ++i < a.counts.size()) ca = a.counts[i], va = !va;
    if (cb == 0 && ++j < b.counts.size()) cb = b.counts[j], vb = !vb;
  }
  const std::uint64_t area_a = rle_area(a), area_b = rle_area(b);
  const std::uint64_t uni = crowd ? area_a : area_a + area_b - inter;
  return uni == 0 ? 0.0 : static_cast<double>(inter) / static_cast<double>(uni);
}

}  // namespace grapebench
