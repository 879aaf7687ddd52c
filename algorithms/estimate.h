// The estimator interface: what a protocol hands an estimator (EstimatorInput) and
// what the estimator answers (Estimate), by output kind: scalars, 3D points,
// detections, per-point class scores.
#pragma once

#include <Eigen/Geometry>
#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "algorithms/point_cloud.h"
#include "algorithms/stereo_pair.h"

namespace grapebench {

// Quantities an estimator can report, each scored against its ground truth.
// SI units inside the program (m3, m); the harness writes cm3 and mm.
// Perimeters are of the sections through the bunch centre normal to the height,
// length and width axis (seed 002 Eqs. 10-12).
// SizeMajor / SizeMinor: seed 003's pair of size measures G_x (Eq. 3), the larger and
// the smaller, scored against the hanging bunch's length and width, larger first.
// HangingHeight / MaxDiameter: seed 001's bounding-volume height and maximum diameter,
// scored against the hanging bunch's vertical extent (without the peduncle) and its
// largest diameter about the vertical through the cutting point.
enum class Quantity {
  Volume,
  Height,
  Length,
  Width,
  PerimeterH,
  PerimeterL,
  PerimeterW,
  SizeMajor,
  SizeMinor,
  HangingHeight,
  MaxDiameter
};
inline constexpr Quantity kAllQuantities[] = {Quantity::Volume,        Quantity::Height,     Quantity::Length,
                                              Quantity::Width,         Quantity::PerimeterH, Quantity::PerimeterL,
                                              Quantity::PerimeterW,    Quantity::SizeMajor,  Quantity::SizeMinor,
                                              Quantity::HangingHeight, Quantity::MaxDiameter};
const char* quantity_name(Quantity q);  // "volume", "height", ..., "perimeter_h"
// (name, quantity) for every quantity: the choices of a scene's `quantities` list.
std::vector<std::pair<std::string, Quantity>> quantity_choices();

// A circle in an image: centre and radius in pixels.
struct Circle {
  double x = 0, y = 0, r = 0;
};
// One detected object (seed 001's berries): its circle and a confidence.
struct Detection {
  Circle circle;
  double score = 1;  // higher is more confident
};

// One instance found in an image (protocol detection): a record of COCO's results
// format. Categories by name: "bunch", "berry", "stalk", "leaf", "cane"
// (bench/image_truth.h). Pixel edges as COCO's: the top-left pixel spans [0, 1).
struct ImageDetection {
  std::string category;
  double score = 1;                    // higher is more confident
  double x = 0, y = 0, w = 0, h = 0;   // box, px
  // The mask, 0 / 1, on the pixel rectangle [mask_x, mask_x + mask_w) x [mask_y, ...):
  // mask_h x mask_w row-major; empty for a box only (scored as its box's pixels, as
  // COCO's loadRes makes a box into a mask).
  int mask_x = 0, mask_y = 0, mask_w = 0, mask_h = 0;
  std::vector<std::uint8_t> mask;
  std::string rle;  // or the mask as COCO's compressed RLE counts over the whole image (external programs)
  double volume = std::numeric_limits<double>::quiet_NaN();  // m3, a bunch's, where the estimator answers it
};

// What one run of an estimator gives the harness.
struct Estimate {
  std::vector<std::pair<Quantity, double>> values;   // scalars, SI units
  std::vector<std::pair<std::string, Vec3>> points;  // named 3D points, m, the input's frame ("cutting_point")
  std::vector<Detection> detections;                 // in the input image's pixels
  std::vector<ImageDetection> instances;             // protocols detection, stereo_pair ("bunch"): in the left image
  Eigen::MatrixXd class_scores;                      // N x K per-point class scores (or 0 x 0)
  bool watertight = false;                           // for volume methods with a mesh
  // Set when the scalars could not be made (the stage that failed); the other outputs
  // (a cutting point, detections) still stand.
  std::string error;
  std::string notes;  // diagnostics (points used, iterations, residuals), into results.csv
};

// One view of a multi-view scan: its segmented, filtered returns in its camera frame
// and the pose the registration found (camera to the cloud's frame).
struct InputView {
  std::string name;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  PointCloud points;  // M x 3, m
};

// The frame a single-frame estimator measures: which view, which ROI, the camera.
struct InputFrame {
  int index = -1;                         // view of the scan
  std::string roi;                        // auto_r | auto_cm | manual_r | manual_cm
  int region = -1;                        // the region's index in the frame
  int width = 0, height = 0;              // pixels
  double fx = 0, fy = 0, cx = 0, cy = 0;  // pixels, OpenCV convention (pixel (u, v) centred at (u, v))
};

// The stereo_pair protocol's oracle ablation (scene key `pipeline.oracle`; seed 001):
// exact images of the left view that replace a stage of the estimator, so that a
// stage's failure is told apart from the image's appearance. Made only when the scene
// asks for it, and its rows then say so; an estimator is otherwise never given truth.
struct StereoOracle {
  std::vector<std::uint8_t> cluster;  // H x W, 1 on the cluster's pixels (berries, pedicels, branches); empty: not given
  RgbImage berry_edges;               // the left view redrawn from the labels: berries white, their outlines black; empty: not given
};

// What a protocol hands an estimator: the cloud and, where the protocol knows them,
// per-point attributes in the same row order (empty otherwise).
struct EstimatorInput {
  PointCloud points;                         // N x 3, m
  PointCloud viewpoints;                     // N x 3, m: the centre of the camera that saw each point
  PointCloud normals;                        // N x 3, unit: the sensor's surface normal at each point
  std::vector<Rgb8> colours;                 // N: the sensor's colour of each point
  std::vector<InputView> views;              // multi_view: the individual views
  std::optional<InputFrame> frame;           // single_frame: the frame and its ROI
  std::shared_ptr<const StereoPair> stereo;  // stereo_pair: the rectified colour pair (no cloud)
  // classification: the class names (K) and, per point, the class index of the
  // training part's points or -1 where the estimator must score (N, or empty).
  std::vector<std::string> classes;
  std::vector<int> train_labels;
  std::shared_ptr<const StereoOracle> oracle;  // stereo_pair's oracle ablation only (above); null otherwise
};

// An estimator with its parameters bound (parsed and range-checked when the scene is
// read, so a bad parameter fails before any work starts).
using BoundEstimator = std::function<Estimate(const EstimatorInput& input)>;

}  // namespace grapebench
