#include "rayspace/accuracy/grid.h"

#include <chrono>

#include "rayspace/emu/grid/tracer.h"
#include "rayspace/emu/tracer.h"

namespace rayspace::accuracy {
namespace {

FrameOutcome Run(const Scene& scene, const SceneBuffers& b, const emu::FrameOptions& fo, Tracer& tracer) {
  FrameOutcome out;
  const auto t0 = std::chrono::steady_clock::now();
  emu::RenderFrame(scene, b, tracer, fo, [&](const emu::Batch& batch) {
    out.hits.push_back(batch.hits ? *batch.hits : std::vector<std::uint64_t>{});
    out.occluded.push_back(batch.occluded ? *batch.occluded : std::vector<std::uint32_t>{});
  });
  out.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

FrameOutcome RunGrid(const Scene& scene, const SceneBuffers& b, const emu::FrameOptions& fo, bool margins) {
  emu::grid::Options o;
  o.margins = margins;
  const auto tracer = emu::MakeGridTracer(b, o);
  FrameOutcome out = Run(scene, b, fo, *tracer);
  for (const emu::GridBatchStats& s : tracer->Stats()) out.tests += s.tests;
  return out;
}

}  // namespace

std::vector<EndToEnd> GridEndToEnd(const Scene& scene, const SceneBuffers& b, const emu::FrameOptions& fo) {
  const auto direct = emu::MakeDirectTracer(b, emu::DirectMode::kAuto);
  const FrameOutcome reference = Run(scene, b, fo, *direct);
  const FrameOutcome plain = RunGrid(scene, b, fo, false), kept = RunGrid(scene, b, fo, true);
  return {{"binning without margins", plain.ms, plain.tests, RaysChanged(plain, reference)},
          {"binning with margins (rayspace)", kept.ms, kept.tests, RaysChanged(kept, reference)},
          {"direct tracer (reference)", reference.ms, 0, 0}};
}

}  // namespace rayspace::accuracy
