#include "bench/protocols/single_frame.h"

#include <algorithm>
#include <chrono>

#include "algorithms/segmentation/ndi_kmeans.h"
#include "bench/protocols/capture.h"

namespace grapebench {

namespace {

bool on_bunch(std::uint8_t label) { return label <= static_cast<std::uint8_t>(Part::Peduncle); }

// ROI_R^M: the annotator's region, here perfect: the frame's filtered returns on the
// cluster (berries, pedicels, rachis; not the peduncle). Empty when fewer than
// `min_berries` berry returns are visible (the annotator finds no cluster).
Region manual_region(const std::vector<std::uint8_t>& label, int min_berries) {
  Region out;
  int berries = 0;
  for (std::size_t i = 0; i < label.size(); ++i) {
    berries += label[i] == static_cast<std::uint8_t>(Part::Berry);
    if (label[i] <= static_cast<std::uint8_t>(Part::Rachis)) out.push_back(static_cast<Eigen::Index>(i));
  }
  if (berries < min_berries) out.clear();
  return out;
}

}  // namespace

FrameReturns frame_returns(const OrganisedCloud& c) {
  std::vector<Vec3> pts;
  FrameReturns out;
  for (std::size_t i = 0; i < c.size(); ++i) {
    if (!c.valid[i]) continue;
    pts.push_back(c.xyz[i].cast<double>());
    out.pixel.push_back(i);
  }
  out.cloud = to_point_cloud(pts);
  return out;
}

namespace {

// The rough regions of each kind asked for, numbered within the frame.
struct Roi {
  std::string kind;
  int index;
  Region region;
};

std::vector<Roi> frame_rois(const PipelineSpec& pl, const PointCloud& cloud, const std::vector<Rgb8>& rgb,
                            const std::vector<std::uint8_t>& label) {
  const auto wants = [&](const char* kind) { return std::find(pl.rois.begin(), pl.rois.end(), kind) != pl.rois.end(); };
  std::vector<Roi> rois;
  if (wants("auto_r") || wants("auto_cm")) {
    const Seed003Detection det = detect_grape_regions(cloud, rgb, pl.roi);
    for (std::size_t j = 0; j < det.regions.size(); ++j) {
      if (wants("auto_r")) rois.push_back({"auto_r", static_cast<int>(j), det.regions[j]});
      if (wants("auto_cm")) {
        rois.push_back(
            {"auto_cm", static_cast<int>(j), roi_from_centre_of_mass(cloud, det.regions[j], pl.roi.roi_radius)});
      }
    }
  }
  if (wants("manual_r") || wants("manual_cm")) {
    const Region m = manual_region(label, pl.manual_min_berry_points);
    if (!m.empty()) {
      if (wants("manual_r")) rois.push_back({"manual_r", 0, m});
      if (wants("manual_cm")) rois.push_back({"manual_cm", 0, roi_from_centre_of_mass(cloud, m, pl.roi.roi_radius)});
    }
  }
  return rois;
}

// What the estimators get for one tuned region: its points in the camera's frame
// (every viewpoint the origin), their sensor normals and colours, and the frame.
EstimatorInput roi_input(const ScanView& view, int index, const Roi& roi, const Region& tuned, const PointCloud& cloud,
                         const std::vector<std::size_t>& pixel) {
  EstimatorInput in;
  const auto n = static_cast<Eigen::Index>(tuned.size());
  in.points.resize(n, 3);
  in.normals.resize(n, 3);
  in.viewpoints = PointCloud::Zero(n, 3);
  for (Eigen::Index i = 0; i < n; ++i) {
    const auto row = tuned[static_cast<std::size_t>(i)];
    const std::size_t px = pixel[static_cast<std::size_t>(row)];
    in.points.row(i) = cloud.row(row);
    in.normals.row(i) = view.cloud.normal[px].cast<double>().transpose();
    in.colours.push_back(view.cloud.rgb[px]);
  }
  const Intrinsics& k = view.camera.K;
  in.frame = InputFrame{index, roi.kind, roi.index, k.width, k.height, k.fx, k.fy, k.opencv_cx(), k.opencv_cy()};
  return in;
}

}  // namespace

void measure_frame(const Scene& scene, const ScanView& view, std::size_t k, const GroundTruth& gt, FrameTally& tally,
                   CaseResult& r) {
  const PipelineSpec& pl = scene.pipeline;
  const OrganisedCloud& c = view.cloud;
  // Every return of the frame (the paper's point cloud), then the view filters with
  // each point's pixel carried along.
  auto [cloud, pixel] = frame_returns(c);
  apply_filters(pl.view_filters, cloud, pixel);
  std::vector<std::uint8_t> label(pixel.size());
  std::vector<Rgb8> rgb(pixel.size());
  for (std::size_t i = 0; i < pixel.size(); ++i) {
    label[i] = c.label[pixel[i]];
    rgb[i] = c.rgb[pixel[i]];
    tally.frame_bunch += on_bunch(label[i]);
  }
  r.points += pixel.size();
  for (const Roi& roi : frame_rois(pl, cloud, rgb, label)) {
    const Region tuned = pl.fine_tune ? fine_tune_region(cloud, rgb, roi.region, pl.roi) : roi.region;
    std::size_t bunch = 0;
    for (const auto row : tuned) bunch += on_bunch(label[static_cast<std::size_t>(row)]);
    if (roi.kind == "auto_r") {
      tally.auto_kept += tuned.size();
      tally.auto_bunch += bunch;
    }
    const std::string error = tuned.empty() ? "fine tuning found no grape-coloured cluster in the ROI" : "";
    const EstimatorInput in = roi_input(view, static_cast<int>(k), roi, tuned, cloud, pixel);
    for (EstimateRow row : run_estimators(scene.estimators, in, gt, error)) {
      row.frame = static_cast<int>(k);
      row.roi = roi.kind;
      row.region = roi.index;
      row.region_precision = tuned.empty() ? 0 : static_cast<double>(bunch) / static_cast<double>(tuned.size());
      r.rows.push_back(std::move(row));
    }
  }
}

void finish_frames(const FrameTally& t, CaseResult& r) {
  r.segmentation_precision = t.auto_kept ? static_cast<double>(t.auto_bunch) / static_cast<double>(t.auto_kept) : 0;
  r.segmentation_recall = t.frame_bunch ? static_cast<double>(t.auto_bunch) / static_cast<double>(t.frame_bunch) : 0;
}

CaseResult run_single_frame(const Condition& condition, int condition_index, const BunchJob& job) {
  FrameTally tally;
  return measure_views(
      condition, condition_index, job,
      [&](const Bunch&, const GroundTruth& truth, const ScanView& view, std::size_t k, CaseResult& r) {
        measure_frame(condition.scene, view, k, truth, tally, r);
      },
      [&](CaseResult& r) { finish_frames(tally, r); });
}

}  // namespace grapebench
