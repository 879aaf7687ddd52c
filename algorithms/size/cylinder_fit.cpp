#include "algorithms/size/cylinder_fit.h"
#include "synth/run_stop.h"

#include <pcl/features/normal_3d.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/sample_consensus/method_types.h>
#include <pcl/sample_consensus/model_types.h>
#include <pcl/search/kdtree.h>
#include <pcl/sample_consensus/msac.h>
#include <pcl/sample_consensus/sac_model_cylinder.h>

#include <algorithm>
#include <cmath>

namespace grapebench {

namespace {

// PCL's cylinder model, polling the run's stop flag (synth/run_stop.h) on each MSAC
// trial: the trials allocate nothing, so a budget could not end them otherwise.
class StoppableCylinder : public pcl::SampleConsensusModelCylinder<pcl::PointXYZ, pcl::Normal> {
 public:
  using Base = pcl::SampleConsensusModelCylinder<pcl::PointXYZ, pcl::Normal>;
  using Base::Base;
  void getDistancesToModel(const Eigen::VectorXf& coefficients, std::vector<double>& distances) const override {
    throw_if_stop_requested();
    Base::getDistancesToModel(coefficients, distances);
  }
};

}  // namespace

CylinderFit cylinder_fit(const PointCloud& cloud, const CylinderFitParams& p) {
  require_points(cloud, 10, "cylinder_fit");
  if (!(p.max_distance >= 1e-4 && p.max_distance <= 0.5)) throw InputError("cylinder_fit: max_distance must lie in [1e-4, 0.5] m");
  if (!(p.min_radius >= 1e-3 && p.max_radius <= 1 && p.min_radius < p.max_radius)) {
    throw InputError("cylinder_fit: need 1e-3 <= min_radius < max_radius <= 1 m");
  }
  if (p.max_iterations < 1 || p.max_iterations > 1000000) throw InputError("cylinder_fit: max_iterations must lie in [1, 1e6]");
  if (!(p.normal_weight >= 0 && p.normal_weight <= 1)) throw InputError("cylinder_fit: normal_weight must lie in [0, 1]");
  if (p.normal_k < 3 || p.normal_k > 500) throw InputError("cylinder_fit: normal_k must lie in [3, 500]");
  const Eigen::RowVector3d mean = cloud.colwise().mean();  // float keeps micrometres near the origin
  auto in = pcl::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
  for (Eigen::Index i = 0; i < cloud.rows(); ++i) {
    const Eigen::RowVector3d q = cloud.row(i) - mean;
    in->push_back(pcl::PointXYZ(static_cast<float>(q(0)), static_cast<float>(q(1)), static_cast<float>(q(2))));
  }
  auto normals = pcl::make_shared<pcl::PointCloud<pcl::Normal>>();
  pcl::NormalEstimation<pcl::PointXYZ, pcl::Normal> ne;
  ne.setInputCloud(in);
  ne.setSearchMethod(pcl::make_shared<pcl::search::KdTree<pcl::PointXYZ>>());
  ne.setKSearch(std::min<int>(p.normal_k, static_cast<int>(cloud.rows()) - 1));
  ne.compute(*normals);
  // What pcl::SACSegmentationFromNormals::segment does (PCL 1.13: the model seeded,
  // MSAC at probability 0.99, coefficients optimised, inliers selected again), with
  // the stoppable model.
  auto model = pcl::make_shared<StoppableCylinder>(in, false);
  model->setInputNormals(normals);
  model->setRadiusLimits(p.min_radius, p.max_radius);
  model->setNormalDistanceWeight(p.normal_weight);
  pcl::MEstimatorSampleConsensus<pcl::PointXYZ> sac(model, p.max_distance);
  sac.setMaxIterations(p.max_iterations);
  sac.setProbability(0.99);
  pcl::Indices inliers;
  Eigen::VectorXf coeff, refined;
  if (sac.computeModel(0)) {
    sac.getInliers(inliers);
    sac.getModelCoefficients(coeff);
    model->optimizeModelCoefficients(inliers, coeff, refined);
    model->selectWithinDistance(refined, p.max_distance, inliers);
  }
  if (inliers.empty() || refined.size() != 7) throw InputError("cylinder_fit: no cylinder found");
  const std::vector<float> coeff_values(refined.data(), refined.data() + 7);
  CylinderFit f;
  f.point = Vec3(coeff_values[0], coeff_values[1], coeff_values[2]) + mean.transpose();
  f.axis = Vec3(coeff_values[3], coeff_values[4], coeff_values[5]).normalized();
  f.radius = coeff_values[6];
  f.diameter = 2 * f.radius;
  double lo = 1e300, hi = -1e300;
  for (auto i : inliers) {
    const double t = (cloud.row(i).transpose() - f.point).dot(f.axis);
    lo = std::min(lo, t);
    hi = std::max(hi, t);
  }
  f.height = hi - lo;
  f.inliers = static_cast<int>(inliers.size());
  return f;
}

const ParamTable<CylinderFitParams>& cylinder_fit_param_table() {
  using P = CylinderFitParams;
  static const ParamTable<P> table =
      ParamTable<P>()
          .real("max_distance", "m", &P::max_distance, 1e-4, 0.5, "inlier distance (seed 003 does not give it)")
          .real("min_radius", "m", &P::min_radius, 1e-3, 1, "smallest cylinder radius")
          .real("max_radius", "m", &P::max_radius, 1e-3, 1, "largest cylinder radius")
          .integer("max_iterations", "count", &P::max_iterations, 1, 1000000, "MSAC trials (pcfitcylinder default)")
          .real("normal_weight", "-", &P::normal_weight, 0, 1, "weight of the normal angle in the distance")
          .integer("normal_k", "count", &P::normal_k, 3, 500, "neighbours for the normals")
          .validate([](const P& p, const ConfigNode& n) {
            if (p.min_radius >= p.max_radius) n.fail("min_radius", "must be below max_radius");
          });
  return table;
}

}  // namespace grapebench
