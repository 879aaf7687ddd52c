#include "algorithms/registry.h"

#include <algorithm>
#include <filesystem>

#include "algorithms/volume/alpha_shape_volume.h"
#include "algorithms/volume/convex_hull_volume.h"
#include "algorithms/size/cylinder_fit.h"
#include "algorithms/volume/cylinder_model_volume.h"
#include "algorithms/classification/dey2012_classification.h"
#include "algorithms/size/ellipsoid_fit.h"
#include "algorithms/volume/ellipsoid_volume.h"
#include "algorithms/external/external_estimator.h"
#include "algorithms/stereo/luo2016_instances.h"
#include "algorithms/stereo/luo2016_stereo.h"
#include "algorithms/cloud/mls_smooth.h"
#include "algorithms/size/pca_box.h"
#include "algorithms/size/percentile_box.h"
#include "algorithms/volume/poisson_volume.h"
#include "algorithms/external/python_estimator.h"
#include "algorithms/size/section_perimeters.h"
#include "algorithms/volume/voxel_volume.h"

namespace grapebench {

namespace {

// Estimators without parameters.
struct NoParams {};
const ParamTable<NoParams>& no_params() {
  static const ParamTable<NoParams> table;
  return table;
}

// A registry line: the estimator reports `quantities`; run(params, cloud, viewpoints).
template <class P, class Run>
RegistryEntry<EstimatorBinding> estimator(std::string type, std::string summary, std::vector<Quantity> quantities,
                                          const ParamTable<P>& table, Run run) {
  return entry<EstimatorBinding>(
      std::move(type), std::move(summary), table, P{}, [quantities, run](const P& p, const ConfigNode&) {
        return EstimatorBinding{quantities,
                                [p, run](const EstimatorInput& in) { return run(p, in.points, in.viewpoints); }};
      });
}

// A pipeline-step line: run(params, cloud).
template <class P, class Run>
RegistryEntry<BoundFilter> step(std::string type, std::string summary, const ParamTable<P>& table, Run run) {
  return entry<BoundFilter>(std::move(type), std::move(summary), table, P{}, [run](const P& p, const ConfigNode&) {
    return BoundFilter([p, run](const PointCloud& c) { return run(c, p); });
  });
}

Estimate volume_only(const VolumeEstimate& v) {
  Estimate e;
  e.values = {{Quantity::Volume, v.volume}};
  e.watertight = v.watertight;
  e.notes = v.notes;
  return e;
}

Estimate scalars(std::vector<std::pair<Quantity, double>> values) {
  Estimate e;
  e.values = std::move(values);
  return e;
}

Estimate size_pair(double a, double b) {
  return scalars({{Quantity::SizeMajor, std::max(a, b)}, {Quantity::SizeMinor, std::min(a, b)}});
}

Estimate poisson(const PoissonParams& q, const PointCloud& c, const PointCloud& viewpoints) {
  if (q.orient == PoissonParams::Orient::Centroid) return volume_only(poisson_volume(c, q));
  if (viewpoints.rows() != c.rows()) {
    throw InputError("poisson: orient: facing needs the camera of every point, and this pipeline gives " +
                     std::to_string(viewpoints.rows()) + " for " + std::to_string(c.rows()) + " points");
  }
  return volume_only(poisson_volume(c, q, viewpoints - c));
}

// The external program's quantities are the scene's, so it builds its own binding.
RegistryEntry<EstimatorBinding> external() {
  return entry<EstimatorBinding>(
      "external", "an external program through the JSON protocol (algorithms/README.md); set `quantities`",
      external_param_table(), ExternalParams{}, [](ExternalParams x, const ConfigNode& n) {
        substitute_scene_dir(x.command, std::filesystem::path(n.file()).parent_path().string());
        substitute_scene_dir(x.readable, std::filesystem::path(n.file()).parent_path().string());
        if (x.input == ExternalParams::Input::LabelledCloud || x.input == ExternalParams::Input::Image)
          x.quantities.clear();  // class scores, or instances, only
        if (x.persistent) x.programs = start_persistent_programs(x);
        return EstimatorBinding{x.quantities, [x](const EstimatorInput& in) { return external_estimate(in, x); },
                                external_input_name(x.input)};
      });
}

// A Python function in-process: imported when the scene is read, so a missing module
// or function fails there with file:line.
RegistryEntry<EstimatorBinding> python() {
  return entry<EstimatorBinding>(
      "python", "a Python function run in-process on numpy arrays (docs/python.md); set `module`",
      python_param_table(), PythonParams{}, [](PythonParams x, const ConfigNode& n) {
        substitute_scene_dir(x.path, std::filesystem::path(n.file()).parent_path().string());
        if (x.input == ExternalParams::Input::LabelledCloud || x.input == ExternalParams::Input::Image)
          x.quantities.clear();
        try {
          x.callable = load_python_function(x);
        } catch (const InputError& e) {
          n.fail("module", e.what());
        }
        return EstimatorBinding{x.quantities, [x](const EstimatorInput& in) { return python_estimate(in, x); },
                                external_input_name(x.input)};
      });
}

using Q = Quantity;

}  // namespace

const Registry<EstimatorBinding>& estimator_registry() {
  static const Registry<EstimatorBinding> registry(
      "estimator",
      {
          estimator("pca_box", "PCA-frame bounding box height/length/width (seed 000 Eq. 5, seed 002 Eqs. 7-9)",
                    {Q::Height, Q::Length, Q::Width}, no_params(),
                    [](const NoParams&, const PointCloud& c, const PointCloud&) {
                      const PcaBox b = pca_box(c);
                      return scalars({{Q::Height, b.height}, {Q::Length, b.length}, {Q::Width, b.width}});
                    }),
          estimator("section_perimeters",
                    "perimeters of the three centre sections, Hobby spline, arc length (seed 002 Eqs. 10-12)",
                    {Q::PerimeterH, Q::PerimeterL, Q::PerimeterW}, section_perimeter_param_table(),
                    [](const SectionPerimeterParams& s, const PointCloud& c, const PointCloud&) {
                      const SectionPerimeters r = section_perimeters(c, s);
                      Estimate e;
                      e.values = {{Q::PerimeterH, r.perimeter(0)},
                                  {Q::PerimeterL, r.perimeter(1)},
                                  {Q::PerimeterW, r.perimeter(2)}};
                      e.notes = "knots " + std::to_string(r.knots[0]) + "/" + std::to_string(r.knots[1]) + "/" +
                                std::to_string(r.knots[2]);
                      return e;
                    }),
          estimator("cylinder_model", "GM: cylinder of diameter max(l, w) and height h (seed 000 Eq. 6)", {Q::Volume},
                    no_params(),
                    [](const NoParams&, const PointCloud& c, const PointCloud&) {
                      return volume_only(cylinder_model_volume(c));
                    }),
          estimator("convex_hull", "CH: convex hull volume (seed 000; CGAL quickhull)", {Q::Volume}, no_params(),
                    [](const NoParams&, const PointCloud& c, const PointCloud&) {
                      return volume_only(convex_hull_volume(c));
                    }),
          estimator("alpha_shape", "AS: solid alpha complex volume (seed 000; CGAL), alpha as a radius in m",
                    {Q::Volume}, alpha_shape_param_table(),
                    [](const AlphaShapeParams& a, const PointCloud& c, const PointCloud&) {
                      return volume_only(alpha_shape_volume(c, a));
                    }),
          estimator(
              "ellipsoid_volume", "4/3 pi r1 r2 r3 of the algebraic ellipsoid fit", {Q::Volume}, no_params(),
              [](const NoParams&, const PointCloud& c, const PointCloud&) { return volume_only(ellipsoid_volume(c)); }),
          estimator("voxel", "VB: voxel counting (seed 000 Eq. 7), voxel edge in m", {Q::Volume},
                    voxel_volume_param_table(),
                    [](const VoxelVolumeParams& v, const PointCloud& c, const PointCloud&) {
                      return volume_only(voxel_volume(c, v));
                    }),
          estimator("poisson",
                    "PB: Poisson reconstruction from MLS normals, signed-tetrahedron volume (seed 000 Eq. 11; PCL, "
                    "CGAL or screened Poisson)",
                    {Q::Volume}, poisson_param_table(), poisson),
          estimator("percentile_box_edges",
                    "G_E: two largest edges of the percentile box, and its volume (seed 003 Alg. 1)",
                    {Q::SizeMajor, Q::SizeMinor, Q::Volume}, percentile_box_param_table(),
                    [](const PercentileBoxParams& b, const PointCloud& c, const PointCloud&) {
                      const PercentileBox box = percentile_box(c, b);
                      Estimate e = size_pair(box.edges[0], box.edges[1]);
                      e.values.push_back({Q::Volume, box.volume()});
                      return e;
                    }),
          estimator("percentile_box_diagonals",
                    "G_D: two largest face diagonals of the percentile box (seed 003 Alg. 1)",
                    {Q::SizeMajor, Q::SizeMinor}, percentile_box_param_table(),
                    [](const PercentileBoxParams& b, const PointCloud& c, const PointCloud&) {
                      const PercentileBox box = percentile_box(c, b);
                      return size_pair(box.diagonals[0], box.diagonals[1]);
                    }),
          estimator("ellipsoid_fit", "G_R: two largest radii of the algebraic ellipsoid fit (seed 003, Petrov's fit)",
                    {Q::SizeMajor, Q::SizeMinor}, ellipsoid_size_param_table(),
                    [](const EllipsoidSizeParams& p, const PointCloud& c, const PointCloud&) {
                      const double k = p.measure == EllipsoidSizeParams::Measure::Radii ? 1.0 : 2.0;
                      const EllipsoidFit f = ellipsoid_fit(c);
                      return size_pair(k * f.radii[0], k * f.radii[1]);
                    }),
          estimator("cylinder_fit", "G_C: diameter and height of the MSAC cylinder fit (seed 003, pcfitcylinder)",
                    {Q::SizeMajor, Q::SizeMinor}, cylinder_fit_param_table(),
                    [](const CylinderFitParams& f, const PointCloud& c, const PointCloud&) {
                      const CylinderFit fit = cylinder_fit(c, f);
                      return size_pair(fit.diameter, fit.height);
                    }),
          entry<EstimatorBinding>(
              "luo2016_stereo",
              "seed 001's system on a rectified colour stereo pair: cutting point, berry circles, revolved bounding "
              "volume (Luo et al. 2016; OpenCV)",
              luo2016_param_table(), Luo2016Params{},
              [](const Luo2016Params& p, const ConfigNode&) {
                return EstimatorBinding{{Q::HangingHeight, Q::MaxDiameter, Q::Volume},
                                        [p](const EstimatorInput& in) { return luo2016_estimate(in, p); },
                                        "stereo_pair"};
              }),
          entry<EstimatorBinding>(
              "luo2016_instances",
              "seed 001's colour segmentation as a bunch detector and its Hough circles as a berry detector, "
              "with the bounding volume per bunch from the stereo pair (Luo et al. 2016; OpenCV)",
              luo2016_instances_param_table(), Luo2016InstancesParams{},
              [](const Luo2016InstancesParams& p, const ConfigNode&) {
                return EstimatorBinding{{}, [p](const EstimatorInput& in) { return luo2016_instances(in, p); }, "image"};
              }),
          entry<EstimatorBinding>(
              "dey2012_classification",
              "seed 004's classifier on a coloured cloud with training labels: saliency and colour features, "
              "LIBSVM's RBF SVM (or Lalonde's GMM), CRF smoothing; class scores per point (Dey et al. 2012)",
              dey2012_param_table(), Dey2012Params{},
              [](const Dey2012Params& p, const ConfigNode&) {
                return EstimatorBinding{
                    {}, [p](const EstimatorInput& in) { return dey2012_estimate(in, p); }, "labelled_cloud"};
              }),
          external(),
          python(),
      });
  return registry;
}

const Registry<BoundFilter>& filter_registry() {
  static const Registry<BoundFilter> registry(
      "pipeline step",
      {
          step("pass_through", "keep the points in an axis-aligned box, m (seed 000 clipping, seed 003 Sect. 2.3)",
               pass_through_param_table(), pass_through),
          step("statistical_outlier",
               "statistical outlier removal, n neighbours and delta sd (seed 002 Sect. 2.1; PCL)",
               outlier_removal_param_table(), statistical_outlier_removal),
          step("voxel_grid", "voxel-grid downsampling to voxel centroids, leaf in m (seed 000; PCL)",
               voxel_grid_param_table(), voxel_grid),
          step("region_growing",
               "region growing on normals/curvature; flat large regions are background (seed 000; PCL)",
               region_growing_param_table(), region_growing_segmentation),
          step("lccp_stalk_removal",
               "remove the stalk: supervoxels + LCCP, thin elongated end segments (seed 002 Eqs. 5-6; PCL)",
               lccp_stalk_param_table(), lccp_stalk_removal),
          step("mls", "moving least squares smoothing and resampling, radius in m (seed 000 Eqs. 3-4; PCL)",
               mls_param_table(),
               [](const PointCloud& c, const MlsParams& f) {
                 SmoothedCloud s = mls_smooth(c, f);
                 FilteredCloud out;
                 out.points = std::move(s.points);
                 out.source = std::move(s.source);
                 out.notes =
                     "smoothed " + std::to_string(out.points.rows()) + " of " + std::to_string(c.rows()) + " points";
                 return out;
               }),
      });
  return registry;
}

}  // namespace grapebench
