#include "bench/protocols/detection.h"

#include <gtest/gtest.h>

#include "bench/image_truth.h"
#include "synth/config.h"

namespace grapebench {
namespace {

ImageDetection answer(std::string category, double x, double y, double w, double h, double score = 1) {
  ImageDetection d;
  d.category = std::move(category), d.x = x, d.y = y, d.w = w, d.h = h, d.score = score;
  return d;
}

const std::vector<std::string> kBunchBerry{"bunch", "berry"};

TEST(DetectionProtocol, BoxOnlyAnswersAreTheirBoxesPixelsAndUnscoredCategoriesAreDropped) {
  int dropped = 0;
  std::vector<std::size_t> source;
  const auto objects = answer_objects({answer("leaf", 0, 0, 5, 5), answer("berry", 2, 3, 4, 5)}, 20, 10, kBunchBerry,
                                      dropped, source);
  ASSERT_EQ(objects.size(), 1u);
  EXPECT_EQ(dropped, 1);
  EXPECT_EQ(source, std::vector<std::size_t>{1});
  EXPECT_EQ(objects[0].category_id, kBerry);
  EXPECT_DOUBLE_EQ(objects[0].area, 20);  // 4 x 5 pixels
  const auto box = rle_box(*objects[0].mask);
  EXPECT_EQ(box, (std::array<double, 4>{2, 3, 4, 5}));
}

TEST(DetectionProtocol, BadAnswersAreErrorsNamingTheInstance) {
  int dropped = 0;
  std::vector<std::size_t> source;
  auto error = [&](ImageDetection d) {
    try {
      answer_objects({answer("bunch", 1, 1, 2, 2), d}, 20, 10, kBunchBerry, dropped, source);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(error(answer("grape", 0, 0, 1, 1)).find("instance 1 (grape): category must be one of"), std::string::npos);
  EXPECT_NE(error(answer("berry", NAN, 0, 1, 1)).find("instance 1 (berry): box must be finite"), std::string::npos);
  EXPECT_NE(error(answer("berry", 0, 0, -1, 1)).find("width and height >= 0"), std::string::npos);
  EXPECT_NE(error(answer("berry", 0, 0, 1, 1, INFINITY)).find("score must be a finite number"), std::string::npos);
  ImageDetection outside = answer("berry", 0, 0, 1, 1);
  outside.mask_x = 18, outside.mask_y = 0, outside.mask_w = 4, outside.mask_h = 1, outside.mask.assign(4, 1);
  EXPECT_NE(error(outside).find("mask must lie in the 20 x 10 image"), std::string::npos);
  ImageDetection short_mask = answer("berry", 0, 0, 1, 1);
  short_mask.mask_w = 2, short_mask.mask_h = 2, short_mask.mask.assign(3, 1);
  EXPECT_NE(error(short_mask).find("hold mask_w x mask_h values"), std::string::npos);
  ImageDetection bad_rle = answer("berry", 0, 0, 1, 1);
  bad_rle.rle = "not runs";
  EXPECT_NE(error(bad_rle).find("instance 1 (berry): segmentation:"), std::string::npos);
}

// Two true bunches side by side, berries in each; the count takes berry answers whose
// box centre falls on the bunch's visible mask; a volume pairs with the bunch its mask
// overlaps, best score first, each true bunch once.
TEST(DetectionProtocol, BerryCountsAndVolumesGoToTheBunchTheyLieOn) {
  const int W = 40, H = 20;
  DetectionView view;
  view.width = W, view.height = H;
  std::vector<int> truth_bunch;
  auto add = [&](int category, int bunch, int u0, int v0, int w, int h) {
    std::vector<std::uint8_t> ones(static_cast<std::size_t>(w) * h, 1);
    CocoObject o;
    o.id = static_cast<std::int64_t>(view.truth.size()) + 1;
    o.category_id = category;
    o.mask = rle_encode(ones.data(), u0, v0, w, h, W, H);
    o.area = static_cast<double>(rle_area(*o.mask));
    o.bbox = rle_box(*o.mask);
    view.truth.push_back(o);
    truth_bunch.push_back(bunch);
  };
  add(kBunch, 0, 0, 0, 20, 20), add(kBunch, 1, 20, 0, 20, 20);
  add(kBerry, 0, 2, 2, 4, 4), add(kBerry, 0, 10, 10, 4, 4), add(kBerry, 1, 25, 5, 4, 4);
  std::vector<ImageDetection> answers{answer("berry", 2, 2, 4, 4), answer("berry", 30, 10, 4, 4),
                                      answer("berry", 32, 2, 4, 4), answer("bunch", 20, 0, 20, 20, 0.9),
                                      answer("bunch", 21, 0, 19, 20, 0.8)};
  answers[3].volume = 2e-4, answers[4].volume = 9e-4;
  int dropped = 0;
  std::vector<std::size_t> source;
  const auto objects = answer_objects(answers, W, H, kBunchBerry, dropped, source);
  EstimateRow base;
  base.estimator = "x";
  const auto rows = detection_rows(base, answers, objects, source, view, truth_bunch, {1e-4, 3e-4}, 0.5);
  std::vector<const EstimateRow*> counts, volumes;
  for (const EstimateRow& r : rows) {
    if (r.quantity == "berry_count") counts.push_back(&r);
    if (r.quantity == "volume") volumes.push_back(&r);
  }
  ASSERT_EQ(counts.size(), 2u);
  EXPECT_EQ(counts[0]->region, 0); EXPECT_DOUBLE_EQ(counts[0]->estimate, 1); EXPECT_DOUBLE_EQ(counts[0]->truth, 2);
  EXPECT_EQ(counts[1]->region, 1); EXPECT_DOUBLE_EQ(counts[1]->estimate, 2); EXPECT_DOUBLE_EQ(counts[1]->truth, 1);
  // The better-scored bunch answer takes bunch 1; the second finds it taken.
  ASSERT_EQ(volumes.size(), 1u);
  EXPECT_EQ(volumes[0]->region, 1);
  EXPECT_DOUBLE_EQ(volumes[0]->estimate, 2e-4);
  EXPECT_DOUBLE_EQ(volumes[0]->truth, 3e-4);
}

}  // namespace
}  // namespace grapebench
