// Per-pass timings of the emulated pipeline on the bundled self-contained scenes.
// Run: build/bench/rayspace_bench [--benchmark_filter=...]; times are medians of repetitions.
#include <benchmark/benchmark.h>

#include <map>

#include "rayspace/emu/frame.h"
#include "rayspace/emu/passes.h"

using namespace rayspace;

namespace {

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
    l.scene = LoadScene(std::string(RAYSPACE_SOURCE_DIR) + "/scenes/" + name, {});
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

}  // namespace

BENCHMARK_CAPTURE(BM_Raster, cornell, "cornell-mirrors.json")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Raster, office, "office.json")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_ShadowTrace, cornell_bvh, "cornell-mirrors.json", emu::DirectMode::kBvh)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_ShadowTrace, cornell_exhaustive, "cornell-mirrors.json", emu::DirectMode::kExhaustive)->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK_CAPTURE(BM_ShadowTrace, office_bvh, "office.json", emu::DirectMode::kBvh)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Frame, cornell, "cornell-mirrors.json")->Unit(benchmark::kMillisecond)->Iterations(3);

BENCHMARK_MAIN();
