// Multi-view registration of turntable scans (seeds 000 and 002), scored by the
// harness against the rig's true poses.
#pragma once

#include "algorithms/point_cloud.h"
#include "synth/param_table.h"

#include <Eigen/Geometry>

#include <string>
#include <vector>

namespace grapebench {

struct IcpParams {
  // Correspondences farther apart than this are dropped, m, [1e-4, 1]. Seeds 000/002
  // give no value; 10 mm is about a third of a berry.
  double max_correspondence_distance = 0.003;
  int max_iterations = 50;              // [1, 10000]
  double transformation_epsilon = 1e-9;  // squared change of the transform to stop, [0, 1]
  double fitness_epsilon = 1e-10;        // change of the mean squared error to stop (m2), [0, 1]
  // Point-to-plane error (normals from the 20 nearest neighbours, PCL) instead of
  // the papers' point-to-point: partial views slide less.
  bool point_to_plane = false;
};
const ParamTable<IcpParams>& icp_param_table();

struct IcpResult {
  Eigen::Isometry3d transform = Eigen::Isometry3d::Identity();  // source -> target
  bool converged = false;
  double fitness = 0;  // mean squared distance of the correspondences, m2
};

// ICP from `initial`. Point-to-point: PCL's IterativeClosestPoint's algorithm and
// convergence criteria in double precision on a k-d tree, correspondences found in
// parallel (the same result at any thread count); point-to-plane: PCL's
// IterativeClosestPointWithNormals. Throws InputError for clouds with fewer than 3
// points or non-finite points.
IcpResult icp_align(const PointCloud& source, const PointCloud& target, const Eigen::Isometry3d& initial,
                    const IcpParams& params);

// How a principal axis gets its sign, which PCA leaves open (seed 000 does not say).
enum class PcaSign {
  // Of the four proper sign choices, the rotation closest to the identity: never a
  // turn above 120 deg (the candidates are the true turn and it composed with a half
  // turn about each axis), and a half turn about a principal axis comes back as none.
  nearest,
  // The first two axes each towards the side holding more of the points' squared
  // projections (Bro, Acar & Kolda 2008, J. Chemometrics 22:135), the third their
  // cross product: the frame turns with a cloud skewed along both axes by any angle.
  // Where either cloud is symmetric about one of them, the nearest rule.
  skew,
};

// Coarse alignment by principal axes (seed 000): centroid onto centroid, the source's
// PCA frame onto the target's, the axes' signs by `sign`.
Eigen::Isometry3d pca_alignment(const PointCloud& source, const PointCloud& target,
                                PcaSign sign = PcaSign::nearest);

// One view as registration sees it: points in its camera frame.
struct RegistrationView {
  PointCloud points;        // N x 3, metres, camera frame
  std::string name;         // "view_00", "bottom"
  // Pose relative to view 0 as the rig nominally has it (turntable angle and the
  // calibrated axis; seed 002 Eq. 1); used only by the known-angle method.
  Eigen::Isometry3d nominal = Eigen::Isometry3d::Identity();
  bool bottom = false;  // seed 002's bottom view
};

struct RegistrationResult {
  std::vector<Eigen::Isometry3d> poses;  // view k frame -> view 0 frame
  std::vector<IcpResult> icp;            // the final ICP of each view (identity for view 0)
  PointCloud merged;                     // every view in view 0's frame
};

// seed 000: views in groups of three (views 1-3 -> A1, 4-6 -> A2, ...), each view
// PCA-aligned then ICP'd onto its group's first view; then the groups the same way
// onto A1.
RegistrationResult register_seed000(const std::vector<RegistrationView>& views, const IcpParams& icp,
                                    int group_size = 3, PcaSign sign = PcaSign::nearest);
// seed 002: each side view rotated by its known turntable angle (Eq. 1) and ICP'd
// onto the merged cloud so far; the bottom view rotated by its nominal mounting,
// centroid-aligned, then ICP on the lowest `bottom_band` metres (Eqs. 3-4).
// `up` is the turntable axis in view 0's frame.
RegistrationResult register_known_angle(const std::vector<RegistrationView>& views, const Eigen::Vector3d& up,
                                        const IcpParams& icp, double bottom_band = 0.03);
// The papers' baseline: every view ICP'd from the identity onto the merged cloud so far.
RegistrationResult register_plain_icp(const std::vector<RegistrationView>& views, const IcpParams& icp);

// Rotation angle of estimate^-1 * truth, deg.
double rotation_error_deg(const Eigen::Isometry3d& estimate, const Eigen::Isometry3d& truth);
// How far the estimate puts the centroid of `points` (the view's own frame) from
// where the truth puts it, m: the translation error where the bunch is, not at the
// camera (a small rotation error moves a camera 1 m away by much more).
double centroid_displacement(const Eigen::Isometry3d& estimate, const Eigen::Isometry3d& truth,
                             const PointCloud& points);

}  // namespace grapebench
