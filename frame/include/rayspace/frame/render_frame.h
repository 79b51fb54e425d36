// One frame as `rayspace render` makes it, with everything its outputs need (the statistics file, the
// summary) but no output of its own: `render` writes and prints it, `bench` times it.
#pragma once
#include <memory>
#include <optional>
#include <vector>

#include <nlohmann/json.hpp>

#include "rayspace/frame/backend_setup.h"
#include "rayspace/emu/frame.h"
#include "rayspace/emu/hierarchy.h"
#include "rayspace/emu/grid/tracer.h"
#include "rayspace/emu/tl/tracer.h"
#include "rayspace/refs/oracle.h"
#include "rayspace/scene.h"
#include "rayspace/frame/memory_estimate.h"
#include "rayspace/frame/render_command.h"
#include "rayspace/frame/statistics.h"
#include "rayspace/frame/timings.h"

namespace rayspace::app {

// The tracers one run builds: the frame's, and the oracle's unless --no-oracle.
struct Tracers {
  std::unique_ptr<Tracer> direct, embree;
  std::unique_ptr<emu::HierarchyTracer> hierarchy;
  std::unique_ptr<emu::TlTracer> tl;
  std::unique_ptr<emu::GridTracer> grid;
  Tracer* frame = nullptr;
  Tracer* oracle = nullptr;
};

// What one frame produced. It refers to the scene's buffers it was rendered from, so it is made in
// place (RenderOnBackend) and never moves.
struct RenderedFrame {
  Tracers tracers;
  std::optional<refs::Oracle> oracle;  // empty with --no-oracle
  double oracle_ms = 0.0;              // time the oracle spent re-tracing
  emu::FrameResult result;
  nlohmann::json tracer;               // the frame tracer's description
  Statistics stats;
  std::vector<Phase> phases;
};

// --closed-models: a warning on stderr for every object of the scene that is not closed.
void WarnOpenModels(const Scene& scene, const SceneBuffers& buffers);

// Whether a hierarchy frame traverses fused (--path, resolving auto).
bool UsesFusedPath(const RenderArgs& args);

// What a render frame holds at once, for its memory estimate: the device's copy of the frame on
// Vulkan, one traversal call's slot streams on the pass-by-pass path.
MemoryUse RenderMemoryUse(const RenderArgs& args);

// The backend --backend names, with the emulated kernels configured for it.
Backend MakeRenderBackend(const RenderArgs& args);

// Renders the frame of `scene` (flattened into `buffers`, checked to fit the backend) at fo's size on
// `backend`, with the tracer args names, each batch re-traced by the oracle unless --no-oracle.
std::unique_ptr<RenderedFrame> RenderOnBackend(const RenderArgs& args, const Scene& scene, const SceneBuffers& buffers,
                                               emu::FrameOptions fo, const Backend& backend);

}  // namespace rayspace::app
