// The exact 2D instances of an image: what a pixel sees (one ray per pixel centre into
// the scene the image shows, row copies included), each instance's visible mask and,
// when asked, its amodal mask (the object alone). The dataset writer writes them
// (bench/dataset_run.h); the detection protocol scores answers against them
// (bench/protocols/detection.h). Categories: kDatasetCategories.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "bench/coco_rle.h"
#include "bench/scene.h"
#include "sensors/camera.h"
#include "sensors/render/ray_render.h"
#include "sensors/ray_scene.h"

namespace grapebench {

// The annotated categories: one table for COCO (ids 1..5) and YOLO (id - 1).
struct DatasetCategory {
  int id;
  const char* name;
  const char* doc;
};
inline constexpr std::array<DatasetCategory, 5> kDatasetCategories{{
    {1, "bunch", "a bunch: its berries, pedicels, rachis and peduncle"},
    {2, "berry", "one berry (its sphere; the pedicel is the bunch's)"},
    {3, "stalk", "the bunch's stalk: its peduncle and the bare rachis above the first branch (seed 001's cutting region)"},
    {4, "leaf", "one leaf (including the copies of the row beside and behind the scene's vine)"},
    {5, "cane", "one cane: the cordon or a shoot"},
}};
enum ImageCategory : int { kBunch = 1, kBerry = 2, kStalk = 3, kLeaf = 4, kCane = 5 };

// One bunch of a case, where it sits in the scene's (possibly merged) bunch.
struct CaseBunch {
  Bunch original;             // as generated (a vine row's bunch before it is hung on the cordon)
  Vec3 shift = Vec3::Zero();  // original -> scene: a translation (synth/vine_row.cpp)
  int berry0 = 0, stem0 = 0;  // its first berry and stem in the scene's bunch
  double branch_z = 0;        // world z of its first branch (the stalk's lower end), scene frame
  std::unique_ptr<RayScene> alone;  // the bunch alone, unshifted: its amodal mask
};

// The case's bunches and the scene's bunch: one, or with `vine_row:` the row of them
// exactly as protocol classification builds it (bench/protocols/classification.cpp).
struct CaseScene {
  std::vector<CaseBunch> bunches;
  Bunch scene_bunch;
};
CaseScene case_scene(const Scene& scene, const BunchJob& job);

// What the labels are cast into: the scene's rays, or the renderer's scene with its row
// copies (renderer ray or cycles), and the leaves as fans of triangles.
struct LabelScene {
  const RayScene* base = nullptr;        // the scene's rays (outlive this)
  std::optional<RayRenderScene> render;  // with the row copies, when the renderer draws them
  const RayScene& rays() const { return render ? render->rays() : *base; }
  std::vector<int> leaf_of_tri, leaf_centre;
  std::vector<std::vector<int>> leaf_triangles;  // per leaf
};
// `rays` must outlive the result.
LabelScene label_scene(const Scene& scene, const RayScene& rays);

// A pixel rectangle, inclusive.
struct PixelBox {
  int u0 = 1 << 30, v0 = 1 << 30, u1 = -1, v1 = -1;
  void add(int u, int v) { u0 = std::min(u0, u), v0 = std::min(v0, v), u1 = std::max(u1, u), v1 = std::max(v1, v); }
  void add(const PixelBox& b) {
    if (b.u1 >= 0) add(b.u0, b.v0), add(b.u1, b.v1);
  }
  bool empty() const { return u1 < 0; }
  int w() const { return u1 - u0 + 1; }
  int h() const { return v1 - v0 + 1; }
};

struct ImageInstance {
  int category = 0;         // ImageCategory
  std::int64_t index = 0;   // the bunch's number in the case, the berry's or cane's index in the scene, the leaf's fan
  int id = 0;               // its value in the instance image, 1..
  int bunch = -1;           // bunch, stalk, berry: its bunch's number in the case
  int berry = -1;           // berry: its index in its bunch's list
  PixelBox box;             // of the visible mask
  std::vector<std::uint8_t> mask;  // visible, box-local (box.h() x box.w()), 0 / 1
  Rle visible;
  std::optional<Rle> amodal;  // visible within it, always
};

struct ImageTruth {
  int width = 0, height = 0;
  std::vector<std::uint16_t> instance_image;  // H x W: the instance's id, 0 none
  std::vector<std::uint8_t> semantic;         // H x W: Part + 1, 0 none
  std::vector<float> depth;                   // H x W: m along the optical axis, 0 none
  std::vector<ImageInstance> instances;       // those of at least `min_pixels` pixels, by id
  double label_seconds = 0, mask_seconds = 0;
};

// Throws std::runtime_error past 65535 instances in one image.
ImageTruth image_truth(const LabelScene& labels, const CaseScene& scene, const Camera& camera, int min_pixels,
                       bool amodal);

}  // namespace grapebench
