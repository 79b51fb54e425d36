// One frame through the emulated pipeline: prep, raster, then per bounce surfaces -> raygen ->
// trim -> trace -> shade, and resolve. Which batches run follows from the scene (its lights,
// materials and max_depth); batches that do not run are reported with the reason.
//
// Lifecycle: construct a FrameRunner with the scene, a tracer and an optional observer; call Run()
// once; read the FrameResult. The observer sees every traced batch (the oracle plugs in there) and
// lives apart from the pipeline.
#pragma once
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "rayspace/digest.h"
#include "rayspace/contract.h"
#include "rayspace/emu/backend.h"
#include "rayspace/emu/passes.h"
#include "rayspace/emu/tracer.h"
#include "rayspace/scene.h"

namespace rayspace::emu {

struct PassRecord {
  std::string name;
  bool ran = false;
  std::string reason;  // why it did not run
  double ms = 0.0;
  std::size_t elements = 0;
  // One of a tracer's own passes (hash, build, traverse, ...), listed before the trace pass whose
  // time includes it; the frame's passes (prep, raster, ..., trace.*, resolve) make up the frame.
  bool in_trace = false;
};

// A traced batch, as handed to the observer.
struct Batch {
  std::string name;  // e.g. "shadow.b0", "reflection.b1"
  std::uint32_t kind = 0;
  int bounce = 0;
  const std::vector<layout::Ray>* rays = nullptr;
  const std::vector<std::uint64_t>* hits = nullptr;      // closest-hit batches
  const std::vector<std::uint32_t>* occluded = nullptr;  // shadow batches
};
using BatchObserver = std::function<void(const Batch&)>;

struct FrameResult {
  int width = 0, height = 0;
  std::size_t triangles = 0;
  std::vector<PassRecord> passes;
  // rays[kind][bounce]: shadow bounces 0..max_depth, reflection/refraction 1..max_depth (index 0 unused).
  std::vector<std::uint64_t> rays[3];
  // Per bounce, the traced shadow rays that reach their light (none occluded it): the frame's lit share
  // is their sum over the shadow rays'.
  std::vector<std::uint64_t> unoccluded_shadow_rays;
  // --primary tl: the eye rays traced, and the pixels whose hit (primitive, or none) differs from the
  // raster's primitive.
  std::uint64_t primary_rays = 0, primary_differing = 0;
  // Area lights: shading points per bounce that see some of an area light's samples but not all (a
  // penumbra), and those that see none of them though they face them (an umbra).
  std::vector<std::uint64_t> penumbra_points, umbra_points;
  DigestLog digest;
  std::vector<std::uint64_t> accum;  // fixed-point colour before resolve
  std::vector<std::uint8_t> rgb;
  GBuffer gbuffer;
  std::vector<glm::vec4> triangle_spheres, object_spheres;
  double total_ms = 0.0;
};

struct FrameOptions {
  int width = 0, height = 0;  // 0: the scene's size
  // Each pass as "k of n" with its time and an ETA on stderr: one line rewritten in place when stderr
  // is a terminal, a line per pass otherwise; `progress_label` (e.g. "impact, emulator") leads it.
  bool progress = false;
  std::string progress_label;
  FramePasses* passes = nullptr;  // the backend of the frame's passes (nullptr: the emulator)
  // Which rays the frame traces (docs/hierarchy.md, "Faithful to the thesis"). --shadow-rule: a shadow
  // ray per covered surface and light (layout::kShadowRuleAll) or only where the light is in front
  // (kShadowRuleLit, the thesis's count); the image is the same either way.
  std::uint32_t shadow_rule = layout::kShadowRuleAll;
  // --shadow-bounces first: shadow rays at bounce 0 only (the thesis's one shadow batch); later
  // bounces shade with every light unoccluded.
  bool shadow_first_bounce_only = false;
  // --primary tl: after the raster, trace an eye ray per pixel with the frame's tracer (a batch of
  // kind kRayPrimary, "primary.b0", checked by the observer like any other) beside the G-buffer,
  // which still drives the shading; FrameResult counts the pixels whose traced primitive differs
  // from the raster's.
  bool trace_primary = false;
};

FrameResult RenderFrame(const Scene& scene, const SceneBuffers& buffers, Tracer& tracer,
                        const FrameOptions& options, const BatchObserver& observer = {});

const char* RayKindName(std::uint32_t kind);

}  // namespace rayspace::emu
