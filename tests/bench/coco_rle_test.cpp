#include "bench/coco_rle.h"

#include <gtest/gtest.h>

#include <random>
#include <stdexcept>

namespace grapebench {
namespace {

// Hand cases: the runs and strings worked out on paper from COCO's definition.
TEST(CocoRle, HandCasesGiveTheirRunsStringsAreasAndBoxes) {
  // 2 x 2, rows [0 1; 1 1]: column-major 0 1 1 1 -> runs 1, 3 -> "13".
  const std::uint8_t a[] = {0, 1, 1, 1};
  const Rle r = rle_encode(a, 2, 2);
  EXPECT_EQ(r.counts, (std::vector<std::uint32_t>{1, 3}));
  EXPECT_EQ(rle_string(r), "13");
  EXPECT_EQ(rle_area(r), 3u);
  EXPECT_EQ(rle_box(r), (std::array<double, 4>{0, 0, 2, 2}));
  // A mask starting with 1 begins with a zero run: 1 x 3 [1 1 0] -> 0, 2, 1.
  const std::uint8_t b[] = {1, 1, 0};
  EXPECT_EQ(rle_encode(b, 3, 1).counts, (std::vector<std::uint32_t>{0, 2, 1}));
  // An empty mask is one run; its box is zeros.
  const std::uint8_t z[6] = {};
  const Rle e = rle_encode(z, 3, 2);
  EXPECT_EQ(e.counts, (std::vector<std::uint32_t>{6}));
  EXPECT_EQ(rle_box(e), (std::array<double, 4>{0, 0, 0, 0}));
  // Runs 0, 40, 2, 1: the fourth is stored as 1 - 40 = -39 ("iN": 25 | 0x20, then 30
  // with the sign bit 0x10), 40 in two groups ("X1").
  const Rle d{1, 43, {0, 40, 2, 1}};
  EXPECT_EQ(rle_string(d), "0X12iN");
  EXPECT_EQ(rle_from_string("0X12iN", 1, 43).counts, d.counts);
}

TEST(CocoRle, BoxEncodingEqualsWholeImageEncodingAndDecodesBack) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 300; ++trial) {
    const int w = 1 + static_cast<int>(rng() % 9), h = 1 + static_cast<int>(rng() % 9);
    const int u0 = static_cast<int>(rng() % w), v0 = static_cast<int>(rng() % h);
    const int bw = 1 + static_cast<int>(rng() % (w - u0)), bh = 1 + static_cast<int>(rng() % (h - v0));
    std::vector<std::uint8_t> box(static_cast<std::size_t>(bw * bh)), full(static_cast<std::size_t>(w * h), 0);
    for (int v = 0; v < bh; ++v)
      for (int u = 0; u < bw; ++u) {
        const std::uint8_t on = rng() % 2;
        box[static_cast<std::size_t>(v * bw + u)] = on;
        full[static_cast<std::size_t>((v0 + v) * w + u0 + u)] = on;
      }
    const Rle a = rle_encode(box.data(), u0, v0, bw, bh, w, h), b = rle_encode(full.data(), w, h);
    ASSERT_EQ(a.counts, b.counts) << "trial " << trial;
    EXPECT_EQ(rle_decode(a), full);
    EXPECT_EQ(rle_from_string(rle_string(a), h, w).counts, a.counts);
    // Area and box against the pixels.
    std::uint64_t area = 0;
    int x0 = w, y0 = h, x1 = -1, y1 = -1;
    for (int v = 0; v < h; ++v)
      for (int u = 0; u < w; ++u)
        if (full[static_cast<std::size_t>(v * w + u)]) ++area, x0 = std::min(x0, u), x1 = std::max(x1, u), y0 = std::min(y0, v), y1 = std::max(y1, v);
    EXPECT_EQ(rle_area(a), area);
    if (area > 0) {
      EXPECT_EQ(rle_box(a), (std::array<double, 4>{double(x0), double(y0), double(x1 - x0 + 1), double(y1 - y0 + 1)}));
    }
  }
}

TEST(CocoRle, IouMatchesPixelCountsAndCrowdDividesByTheDetection) {
  std::mt19937 rng(11);
  for (int trial = 0; trial < 100; ++trial) {
    const int w = 7, h = 5;
    std::vector<std::uint8_t> p(35), q(35);
    for (auto& x : p) x = rng() % 3 == 0;
    for (auto& x : q) x = rng() % 2 == 0;
    int inter = 0, uni = 0, np = 0;
    for (int i = 0; i < 35; ++i) inter += p[i] && q[i], uni += p[i] || q[i], np += p[i];
    const Rle a = rle_encode(p.data(), w, h), b = rle_encode(q.data(), w, h);
    EXPECT_DOUBLE_EQ(rle_iou(a, b), uni ? double(inter) / uni : 0.0);
    EXPECT_DOUBLE_EQ(rle_iou(a, b, true), np ? double(inter) / np : 0.0);
  }
  const Rle small{2, 2, {4}};
  const Rle big{3, 2, {6}};
  EXPECT_THROW(rle_iou(small, big), std::invalid_argument);
}

TEST(CocoRle, MalformedStringsAreRefusedWithTheReason) {
  EXPECT_THROW(rle_from_string("13", 3, 3), std::invalid_argument);    // covers 4 of 9 pixels
  EXPECT_THROW(rle_from_string("1 3", 2, 2), std::invalid_argument);   // a space
  EXPECT_THROW(rle_from_string("X", 2, 2), std::invalid_argument);     // ends inside a run
  EXPECT_THROW(rle_from_string("00iN", 2, 2), std::invalid_argument);  // a negative run
  EXPECT_THROW(rle_from_string("13", -1, 2), std::invalid_argument);
  try {
    rle_from_string("1~", 2, 2);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("character 1"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace grapebench
