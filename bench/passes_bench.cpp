// Per-pass timings of the emulated pipeline on the bundled self-contained scenes.
// Run: build/bench/rayspace_bench [--benchmark_filter=...]; times are medians of repetitions.
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdlib>
#include <map>

#include "rayspace/emu/cone_cull.h"
#include "rayspace/emu/frame.h"
#include "rayspace/emu/hierarchy.h"
#include "rayspace/emu/passes.h"
#include "rayspace/parallel.h"
#include "rayspace/workgroup.h"

using namespace rayspace;

namespace {

// The emulated passes run unchecked, as `rayspace render` runs them, on the benchmarks' thread; the
// workgroup benchmarks below set checking per dispatch.
const ScopedSettings kUnchecked([](Settings& s) { s.check = false; });

struct Loaded {
  Scene scene;
  SceneBuffers buffers;
  layout::FrameConstants fc;
};

const Loaded& Get(const std::string& name) {
  static std::map<std::string, Loaded> cache;
  auto it = cache.find(name);
  if (it == cache.end()) {
    Loaded l;
    LoadOptions lo;
    if (const char* data = std::getenv("RAYSPACE_DATA")) lo.data_root = data;
    l.scene = LoadScene(std::string(RAYSPACE_SOURCE_DIR) + "/scenes/" + name, lo);
    l.buffers = FlattenScene(l.scene);
    l.fc = MakeFrameConstants(l.scene, l.buffers, 512, 512);
    it = cache.emplace(name, std::move(l)).first;
  }
  return it->second;
}

void BM_Raster(benchmark::State& state, const char* scene) {
  const Loaded& l = Get(scene);
  for (auto _ : state) benchmark::DoNotOptimize(emu::PassRaster({.frame = l.fc, .scene = &l.buffers}));
  state.counters["tris/s"] = benchmark::Counter(static_cast<double>(l.buffers.triangles.size()), benchmark::Counter::kIsIterationInvariantRate);
}

void BM_ShadowTrace(benchmark::State& state, const char* scene, emu::DirectMode mode) {
  const Loaded& l = Get(scene);
  const auto g = emu::PassRaster({.frame = l.fc, .scene = &l.buffers});
  const auto surfaces = emu::PassSurfacesFromGBuffer(emu::SurfacesCall(l.fc, g, l.buffers));
  const auto sparse = emu::PassRaygenShadow({.kind = layout::kRayShadow, .frame = l.fc, .surfaces = surfaces, .scene = &l.buffers});
  const auto rays = emu::PassTrim({.kind = layout::kRayShadow, .rays = sparse.rays, .flags = sparse.flags}).rays;
  auto tracer = emu::MakeDirectTracer(l.buffers, mode);
  std::vector<std::uint32_t> occ;
  for (auto _ : state) tracer->Occluded(rays, occ);
  state.counters["rays/s"] = benchmark::Counter(static_cast<double>(rays.size()), benchmark::Counter::kIsIterationInvariantRate);
}

void BM_Frame(benchmark::State& state, const char* scene) {
  const Loaded& l = Get(scene);
  auto tracer = emu::MakeDirectTracer(l.buffers, emu::DirectMode::kAuto);
  emu::FrameOptions fo;
  for (auto _ : state) benchmark::DoNotOptimize(emu::RenderFrame(l.scene, l.buffers, *tracer, fo));
}

// The fused crsh frame (flat, 512x512) with the top level's group culling (emu/cone_cull.h) and
// without it (a margin no group clears). Run with --benchmark_enable_random_interleaving=true and
// repetitions so both see the same machine. Sponza needs RAYSPACE_DATA.
void BM_FusedFrameCull(benchmark::State& state, const char* scene, bool cull) {
  if (std::string(scene) == "sponza.json" && !std::getenv("RAYSPACE_DATA")) {
    state.SkipWithError("RAYSPACE_DATA is not set");
    return;
  }
  const Loaded& l = Get(scene);
  emu::HierarchyConfig cfg;
  cfg.fused = true;
  auto tracer = emu::MakeHierarchyTracer(l.buffers, cfg);
  emu::FrameOptions fo;
  std::uint64_t culled = 0;
  const ScopedSettings margin([&](Settings& s) {
    s.cull_margin = cull ? emu::cone::kCullMargin : INFINITY;
    s.culled_slots = &culled;
  });
  for (auto _ : state) benchmark::DoNotOptimize(emu::RenderFrame(l.scene, l.buffers, *tracer, fo));
  state.counters["culled/frame"] = benchmark::Counter(static_cast<double>(culled), benchmark::Counter::kAvgIterations);
}

// The workgroup model's cost (docs/workgroups.md): a 1M-element inclusive scan of blocks of 256, as
// Hillis-Steele in shared memory and as a subgroup scan, with the checker on and off, against the same
// Hillis-Steele loops run per block by plain ParallelFor. Block sums are not carried across blocks.
constexpr std::uint32_t kScanN = 1u << 20, kScanL = 256;

std::vector<std::uint32_t> ScanInput() {
  std::vector<std::uint32_t> v(kScanN);
  for (std::uint32_t i = 0; i < kScanN; ++i) v[i] = i * 2654435761u;
  return v;
}

void BM_ScanHillisSteele(benchmark::State& state, bool check) {
  const auto in = ScanInput();
  std::vector<std::uint32_t> out(kScanN);
  for (auto _ : state) {
    wg::Dispatch("bench.scan", kScanN / kScanL, kScanL, [&](wg::Workgroup& w) {
      auto& tile = w.Shared<std::uint32_t>(kScanL);
      auto t = w.Private<std::uint32_t>();
      w.Phase([&](wg::Inv& i) { tile[i.local_id] = in[i.global_id]; });
      w.Barrier();
      for (std::uint32_t off = 1; off < kScanL; off *= 2) {
        w.Phase([&](wg::Inv& i) { t[i] = i.local_id >= off ? static_cast<std::uint32_t>(tile[i.local_id - off]) : 0u; });
        w.Barrier();
        w.Phase([&](wg::Inv& i) { tile[i.local_id] += t[i]; });
        w.Barrier();
      }
      w.Phase([&](wg::Inv& i) { out[i.global_id] = tile[i.local_id]; });
    }, {.check = check});
    benchmark::DoNotOptimize(out.data());
  }
}

void BM_ScanSubgroup(benchmark::State& state, bool check) {
  const auto in = ScanInput();
  std::vector<std::uint32_t> out(kScanN);
  for (auto _ : state) {
    wg::Dispatch("bench.scan_subgroup", kScanN / kScanL, kScanL, [&](wg::Workgroup& w) {
      auto& totals = w.Shared<std::uint32_t>(kScanL / 8);
      auto v = w.Private<std::uint32_t>();
      w.Phase([&](wg::Inv& i) { v[i] = in[i.global_id]; });
      auto s = w.SubgroupInclusiveAdd(v);
      w.Phase([&](wg::Inv& i) {
        if (i.lane == i.subgroup_size - 1) totals[i.subgroup_id] = s[i];
      });
      w.Barrier();
      w.Phase([&](wg::Inv& i) {
        for (std::uint32_t k = 0; k < i.subgroup_id; ++k) s[i] += totals[k];
        out[i.global_id] = s[i];
      });
    }, {.check = check});
    benchmark::DoNotOptimize(out.data());
  }
}

void BM_ScanParallelFor(benchmark::State& state) {
  const auto in = ScanInput();
  std::vector<std::uint32_t> out(kScanN);
  for (auto _ : state) {
    ParallelFor(kScanN / kScanL, [&](std::size_t b) {
      std::uint32_t tile[kScanL], t[kScanL];
      for (std::uint32_t l = 0; l < kScanL; ++l) tile[l] = in[b * kScanL + l];
      for (std::uint32_t off = 1; off < kScanL; off *= 2) {
        for (std::uint32_t l = 0; l < kScanL; ++l) t[l] = l >= off ? tile[l - off] : 0u;
        for (std::uint32_t l = 0; l < kScanL; ++l) tile[l] += t[l];
      }
      for (std::uint32_t l = 0; l < kScanL; ++l) out[b * kScanL + l] = tile[l];
    });
    benchmark::DoNotOptimize(out.data());
  }
}

}  // namespace

BENCHMARK_CAPTURE(BM_Raster, cornell, "cornell-mirrors.json")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Raster, office, "office.json")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_ShadowTrace, cornell_bvh, "cornell-mirrors.json", emu::DirectMode::kBvh)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_ShadowTrace, cornell_exhaustive, "cornell-mirrors.json", emu::DirectMode::kExhaustive)->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK_CAPTURE(BM_ShadowTrace, office_bvh, "office.json", emu::DirectMode::kBvh)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Frame, cornell, "cornell-mirrors.json")->Unit(benchmark::kMillisecond)->Iterations(3);
BENCHMARK_CAPTURE(BM_FusedFrameCull, office_cull, "office.json", true)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_FusedFrameCull, office_no_cull, "office.json", false)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_FusedFrameCull, sponza_cull, "sponza.json", true)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_FusedFrameCull, sponza_no_cull, "sponza.json", false)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_ScanHillisSteele, checked, true)->Unit(benchmark::kMillisecond)->Repetitions(5)->ReportAggregatesOnly();
BENCHMARK_CAPTURE(BM_ScanHillisSteele, unchecked, false)->Unit(benchmark::kMillisecond)->Repetitions(5)->ReportAggregatesOnly();
BENCHMARK_CAPTURE(BM_ScanSubgroup, checked, true)->Unit(benchmark::kMillisecond)->Repetitions(5)->ReportAggregatesOnly();
BENCHMARK_CAPTURE(BM_ScanSubgroup, unchecked, false)->Unit(benchmark::kMillisecond)->Repetitions(5)->ReportAggregatesOnly();
BENCHMARK(BM_ScanParallelFor)->Unit(benchmark::kMillisecond)->Repetitions(5)->ReportAggregatesOnly();

BENCHMARK_MAIN();
