// The simulated GPU's speed (docs/simulator.md, "Speed"): lane-instructions a second of the kernels'
// own SPIR-V, for a cornell-mirrors frame whose every compute pass runs on the simulator (crsh, pass
// by pass) and for the trim kernel (a workgroup scan) alone, with every checker on and with none.
// Run: build/bench/rayspace_sim_bench [--benchmark_repetitions=5 --benchmark_enable_random_interleaving=true]
#include <benchmark/benchmark.h>

#include <memory>
#include <string>

#include "rayspace/emu/frame.h"
#include "rayspace/emu/hierarchy.h"
#include "rayspace/emu/passes.h"
#include "rayspace/gpu/backend.h"
#include "rayspace/gpu/passes.h"
#include "rayspace/scene.h"
#include "rayspace/workgroup.h"

using namespace rayspace;

namespace {

// The emulator's own checker is not measured here (off on the benchmarks' thread).
const ScopedSettings kUnchecked([](Settings& s) { s.check = false; });

struct Device {
  std::unique_ptr<gpu_backend::VulkanPasses> gpu;
  std::string error;
};

Device MakeDevice(bool checks) {
  sim::DeviceConfig cfg;
  cfg.checks = checks ? sim::Checks{} : sim::Checks::None();
  Device d;
  if (const vk::Status st = gpu_backend::VulkanPasses::Create(vk::Context::kSimulatedDevice, {}, d.gpu, 64, {}, cfg); !st)
    d.error = st.message;
  return d;
}

const Scene& Cornell() {
  static const Scene scene = LoadScene(std::string(RAYSPACE_SOURCE_DIR) + "/scenes/cornell-mirrors.json", {});
  return scene;
}

void Report(benchmark::State& state, const vk::Context& ctx, std::uint64_t before) {
  state.counters["lane-instr/s"] =
      benchmark::Counter(static_cast<double>(ctx.simulated_instructions() - before), benchmark::Counter::kIsRate);
}

void BM_SimFrame(benchmark::State& state, bool checks) {
  Device d = MakeDevice(checks);
  if (!d.gpu) return state.SkipWithError(d.error.c_str());
  const SceneBuffers buffers = FlattenScene(Cornell());
  auto frame = gpu_backend::MakeVulkanFramePasses(*d.gpu);
  auto hierarchy = gpu_backend::MakeVulkanHierarchyPasses(*d.gpu);
  emu::HierarchyConfig hc;
  hc.passes = hierarchy.get();
  auto tracer = emu::MakeHierarchyTracer(buffers, hc);
  emu::FrameOptions fo;
  fo.width = fo.height = 16;
  fo.passes = frame.get();
  const std::uint64_t before = d.gpu->context().simulated_instructions();
  for (auto _ : state) benchmark::DoNotOptimize(emu::RenderFrame(Cornell(), buffers, *tracer, fo));
  Report(state, d.gpu->context(), before);
}

void BM_SimTrim(benchmark::State& state, bool checks) {
  Device d = MakeDevice(checks);
  if (!d.gpu) return state.SkipWithError(d.error.c_str());
  const SceneBuffers buffers = FlattenScene(Cornell());
  const auto fc = MakeFrameConstants(Cornell(), buffers, 128, 128);
  const auto g = emu::PassRaster({.frame = fc, .scene = &buffers});
  const auto surfaces = emu::PassSurfacesFromGBuffer(emu::SurfacesCall(fc, g, buffers));
  const auto sparse = emu::PassRaygenShadow({.kind = layout::kRayShadow, .frame = fc, .surfaces = surfaces, .scene = &buffers});
  const emu::call::Trim call{.kind = layout::kRayShadow, .rays = sparse.rays, .flags = sparse.flags};
  gpu_backend::VulkanOut<emu::call::Trim> out;
  const std::uint64_t before = d.gpu->context().simulated_instructions();
  for (auto _ : state)
    if (const vk::Status st = d.gpu->Run(call, out); !st) return state.SkipWithError(st.message.c_str());
  Report(state, d.gpu->context(), before);
}

}  // namespace

BENCHMARK_CAPTURE(BM_SimFrame, cornell16_checks_on, true)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_SimFrame, cornell16_checks_off, false)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_SimTrim, cornell128_checks_on, true)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_SimTrim, cornell128_checks_off, false)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_MAIN();
