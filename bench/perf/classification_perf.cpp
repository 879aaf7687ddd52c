// Google Benchmark: seed 004's per-point steps on the test cloud of scenes/
// seed004_green.yaml (its row section reconstructed by the noise-model path), beside
// Open3D's EstimatePerPointCovariances on the same cloud and radius, in the same run.
// Open3D parallelises with OpenMP and grapebench with TBB: run with OMP_NUM_THREADS=1;
// every benchmark here holds TBB to one thread, so one core meets one core.
//   BM_saliency_*: grapebench's features at 1 scale (covariance + eigenvalues per point,
//                  nanoflann, double precision) and at the scene's 2 scales.
//   BM_open3d_covariances: Open3D's covariances alone (no eigenvalues), KDTreeFlann
//                  radius search.
//   BM_svm_predict: LIBSVM probabilities of the scene's s2_rgb model, points per second.
//   BM_crf: the CRF on the test points with those probabilities (the scene's s2_rgb_crf).
#include <benchmark/benchmark.h>
#include <open3d/geometry/KDTreeSearchParam.h>
#include <open3d/geometry/PointCloud.h>
#include <tbb/global_control.h>

#include "algorithms/classification/crf_smoothing.h"
#include "algorithms/classification/dey2012_classification.h"
#include "bench/protocols/capture.h"
#include "bench/protocols/classification.h"
#include "bench/scene_file.h"
#include "synth/rng.h"

namespace {

using namespace grapebench;

struct Data {
  PointCloud points;  // the whole fused row, m
  std::vector<Rgb8> colours;
  std::vector<int> train;
  std::shared_ptr<open3d::geometry::PointCloud> o3d;
  Eigen::MatrixXd x_train, x_test;  // s2_rgb features, standardised
  std::vector<int> y_train;
  PointCloud test_points;
};

const Data& data() {
  static const Data d = [] {
    Data out;
    const SceneSet set = load_scene_set(GRAPEBENCH_SOURCE_DIR "/scenes/seed004_green.yaml");
    const Scene& scene = set.conditions.front().scene;
    const BunchJob job = bunch_jobs(scene).front();
    const RayScene rays = build_row(scene, job);
    const Scan scan = scan_bunch(rays, *scene.sensor, *scene.rig, scene.background, scan_seed(job));
    CaseResult r;
    FusedCloud cloud = reconstruct(scene.pipeline, scan, derive_seed(job.seed, 0x3d5), r);
    std::vector<int> truth;
    out.train = split_row(cloud, scene.pipeline.split_gap, truth);
    out.points = to_point_cloud(cloud.points);
    out.colours.assign(cloud.colours.begin(), cloud.colours.end());
    out.o3d = std::make_shared<open3d::geometry::PointCloud>(cloud.points);
    SaliencyParams sp;  // the scene's s2_rgb
    const SaliencyFeatures f = saliency_features(out.points, out.colours, sp);
    Rng rng(1);
    std::vector<Eigen::Index> tr, te;
    std::vector<int> per_class(3, 0);
    for (std::size_t i = 0; i < out.train.size(); ++i) {
      const int c = out.train[i];
      if (c < 0) te.push_back(static_cast<Eigen::Index>(i));
      else if (per_class[static_cast<std::size_t>(c)] < 1500 && rng.uniform() < 0.2)
        tr.push_back(static_cast<Eigen::Index>(i)), ++per_class[static_cast<std::size_t>(c)];
    }
    Eigen::MatrixXd xt(static_cast<Eigen::Index>(tr.size()), f.features.cols()),
        xs(static_cast<Eigen::Index>(te.size()), f.features.cols());
    for (std::size_t i = 0; i < tr.size(); ++i) {
      xt.row(static_cast<Eigen::Index>(i)) = f.features.row(tr[i]);
      out.y_train.push_back(out.train[static_cast<std::size_t>(tr[i])]);
    }
    out.test_points.resize(static_cast<Eigen::Index>(te.size()), 3);
    for (std::size_t i = 0; i < te.size(); ++i) {
      xs.row(static_cast<Eigen::Index>(i)) = f.features.row(te[i]);
      out.test_points.row(static_cast<Eigen::Index>(i)) = out.points.row(te[i]);
    }
    const FeatureScaling s = fit_scaling(xt);
    out.x_train = s.apply(xt);
    out.x_test = s.apply(xs);
    return out;
  }();
  return d;
}

void BM_saliency(benchmark::State& state) {
  const tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
  const Data& d = data();
  SaliencyParams p;
  p.scales = static_cast<int>(state.range(0));
  p.colour = false;
  for (auto _ : state) benchmark::DoNotOptimize(saliency_features(d.points, {}, p).features.data());
  state.SetItemsProcessed(state.iterations() * d.points.rows());
  state.counters["points"] = static_cast<double>(d.points.rows());
}
BENCHMARK(BM_saliency)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_open3d_covariances(benchmark::State& state) {
  const Data& d = data();
  for (auto _ : state) {
    const auto cov = open3d::geometry::PointCloud::EstimatePerPointCovariances(
        *d.o3d, open3d::geometry::KDTreeSearchParamRadius(SaliencyParams{}.radius));
    benchmark::DoNotOptimize(cov.data());
  }
  state.SetItemsProcessed(state.iterations() * d.points.rows());
}
BENCHMARK(BM_open3d_covariances)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_svm_predict(benchmark::State& state) {
  const tbb::global_control threads(tbb::global_control::max_allowed_parallelism, static_cast<std::size_t>(state.range(0)));
  const Data& d = data();
  static const SvmModel model = train_svm(d.x_train, d.y_train, 3, SvmParams{}, 1);
  const Eigen::MatrixXd x = d.x_test.topRows(std::min<Eigen::Index>(20000, d.x_test.rows()));
  for (auto _ : state) benchmark::DoNotOptimize(svm_probabilities(model, x).data());
  state.SetItemsProcessed(state.iterations() * x.rows());
  state.counters["support_vectors"] = model.support_vectors();
}
BENCHMARK(BM_svm_predict)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_crf(benchmark::State& state) {
  const tbb::global_control one(tbb::global_control::max_allowed_parallelism, 1);
  const Data& d = data();
  static const Eigen::MatrixXd p = svm_probabilities(train_svm(d.x_train, d.y_train, 3, SvmParams{}, 1), d.x_test);
  for (auto _ : state) benchmark::DoNotOptimize(crf_smoothing(d.test_points, p, CrfParams{}).labels.data());
  state.SetItemsProcessed(state.iterations() * p.rows());
}
BENCHMARK(BM_crf)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);

}  // namespace

BENCHMARK_MAIN();
