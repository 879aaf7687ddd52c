// Cylinder fit by M-estimator sample consensus (seed 003 Sect. II-B3: MATLAB's
// pcfitcylinder, MSAC; here PCL's SACSegmentationFromNormals with SAC_MSAC).
#pragma once

#include "algorithms/point_cloud.h"
#include "synth/param_table.h"

namespace grapebench {

struct CylinderFitParams {
  // Inlier distance, m, [1e-4, 0.5]. Seed 003 does not give pcfitcylinder's
  // maxDistance; 1 cm is a few D435 noise levels at 1.5 m.
  double max_distance = 0.01;
  double min_radius = 0.01, max_radius = 0.3;  // m, [1e-3, 1]
  int max_iterations = 1000;                   // [1, 1e6]; MATLAB pcfitcylinder MaxNumTrials default
  double normal_weight = 0.1;                  // weight of the normal angle, [0, 1]
  int normal_k = 20;                           // neighbours for normals, [3, 500]
};
const ParamTable<CylinderFitParams>& cylinder_fit_param_table();

struct CylinderFit {
  Vec3 point = Vec3::Zero();          // on the axis, m
  Vec3 axis = Vec3::UnitZ();          // unit
  double radius = 0;                  // m
  double diameter = 0;                // m, seed 003's G_C diameter
  double height = 0;                  // m, extent of the inliers along the axis (G_C height)
  int inliers = 0;
};

// PCL's random generator is seeded with a fixed value, so the fit is deterministic.
// Throws InputError for fewer than 10 points, non-finite points, bad parameters or no
// cylinder found.
CylinderFit cylinder_fit(const PointCloud& cloud, const CylinderFitParams& params = {});

}  // namespace grapebench
