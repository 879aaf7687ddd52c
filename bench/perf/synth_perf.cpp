// Google Benchmark: bunches generated per second per preset (generation alone, and
// generation plus the full exact ground truth), per OIV compactness class, and the mesh.
#include "synth/generate.h"
#include "synth/ground_truth.h"
#include "synth/mesh.h"
#include "synth/params.h"
#include "synth/rng.h"

#include <benchmark/benchmark.h>

namespace {

using namespace grapebench;

void BM_Generate(benchmark::State& state, std::string name) {
  const BunchParams p = preset(name);
  std::uint64_t i = 0;
  for (auto _ : state) {
    Bunch b = generate_bunch(p, derive_seed(7, i++));
    benchmark::DoNotOptimize(b.berries.data());
  }
  state.counters["bunches_per_s"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}

// The OIV 204 classes against the preset's own setting (BM_Generate/table_red) in the
// same run: classes 6-9 pack harder (pull, pressing, pedicel stretch).
void BM_GenerateOivClass(benchmark::State& state, std::string name) {
  BunchParams p = preset(name);
  p.oiv_compactness = static_cast<int>(state.range(0));
  std::uint64_t i = 0;
  for (auto _ : state) {
    Bunch b = generate_bunch(p, derive_seed(7, i++));
    benchmark::DoNotOptimize(b.berries.data());
  }
  state.counters["bunches_per_s"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}

// A flat side (depth 0.3) (1), a wing (2) and a bent main axis (3) against the preset's
// own setting (0) in the same run: a flat bunch is packed twice (once round, to place
// its wall).
void BM_GenerateAsymmetric(benchmark::State& state, std::string name) {
  BunchParams p = preset(name);
  p.flat_side_probability = state.range(0) == 1 ? 1 : 0;
  p.wing_probability = state.range(0) == 2 ? 1 : 0;
  p.bend_probability = state.range(0) == 3 ? 1 : 0;
  std::uint64_t i = 0;
  for (auto _ : state) {
    Bunch b = generate_bunch(p, derive_seed(7, i++));
    benchmark::DoNotOptimize(b.berries.data());
  }
  state.counters["bunches_per_s"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}

void BM_GenerateWithGroundTruth(benchmark::State& state, std::string name) {
  const BunchParams p = preset(name);
  std::uint64_t i = 0;
  for (auto _ : state) {
    const Bunch b = generate_bunch(p, derive_seed(7, i++));
    GroundTruth g = compute_ground_truth(b, p.density);
    benchmark::DoNotOptimize(g.volume.solid);
  }
  state.counters["bunches_per_s"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}

void BM_VolumeOnly(benchmark::State& state, std::string name) {
  const Bunch b = generate_bunch(preset(name), 7);
  for (auto _ : state) {
    VolumeTerms v = solid_volume_terms(b);
    benchmark::DoNotOptimize(v.solid);
  }
}

void BM_Mesh(benchmark::State& state) {
  const Bunch b = generate_bunch(preset("table-red"), 7);
  MeshOptions o;
  o.sphere_subdivisions = static_cast<int>(state.range(0));
  for (auto _ : state) {
    TriMesh m = bunch_mesh(b, o);
    benchmark::DoNotOptimize(m.faces.data());
  }
}

}  // namespace

BENCHMARK_CAPTURE(BM_Generate, table_red, std::string("table-red"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Generate, wine_red, std::string("wine-red"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Generate, summer_black, std::string("summer-black"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Generate, green_table, std::string("green-table"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_GenerateOivClass, table_red, std::string("table-red"))->Arg(1)->Arg(5)->Arg(9)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_GenerateAsymmetric, table_red, std::string("table-red"))->Arg(0)->Arg(1)->Arg(2)->Arg(3)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_GenerateWithGroundTruth, table_red, std::string("table-red"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_GenerateWithGroundTruth, wine_red, std::string("wine-red"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_GenerateWithGroundTruth, summer_black, std::string("summer-black"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_GenerateWithGroundTruth, green_table, std::string("green-table"))->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_VolumeOnly, table_red, std::string("table-red"))->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Mesh)->Arg(2)->Arg(4)->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
