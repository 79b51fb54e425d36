// What a divergence does to the picture. The diff feeds both backends the same inputs, so after the
// first divergent pass it says nothing of the frame each backend would make on its own. Here the
// frame runs once more on each side alone (the emulator's passes, then the Vulkan kernels' with
// the same planted fault), and the two frames' final hits and pixels are compared; every ray whose
// final hit changes is judged by the exact oracle (refs/oracle.h).
#pragma once
#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "rayspace/emu/frame.h"
#include "rayspace/emu/passes.h"
#include "rayspace/emu/tracer.h"
#include "rayspace/scene.h"

namespace rayspace::app {

// One side's passes: the frame's and the hierarchy's.
struct ImpactSide {
  emu::FramePasses* frame = nullptr;
  emu::HierarchyPasses* hierarchy = nullptr;
};

// The frame's tracer over a side's hierarchy passes (a host tracer ignores them). A ray-space
// hierarchy appends every final ray-triangle test it runs to `candidate_log` (HierarchyConfig's hook);
// other tracers leave it empty.
using ImpactTracerFactory = std::function<std::unique_ptr<Tracer>(emu::HierarchyPasses&, std::vector<std::uint64_t>* candidate_log)>;

// The final ray-triangle tests the emulator's frame ran and the Vulkan side's did not, each run
// alone: a lost test that meets its triangle (the final pass's own watertight test, the ray's own
// surface excluded) is a hit the loss can take away, hidden in this frame only if a closer hit or
// another occluder stands before it. With no lost test meeting its triangle, the loss provably
// changes no hit in this frame.
struct LostTests {
  bool logged = false;           // the tracer logs its final tests (the ray-space hierarchy)
  std::size_t lost = 0, added = 0;
  std::size_t lost_hitting = 0;  // lost tests whose ray meets the triangle within its segment
  std::string first_hitting;     // "BATCH ray R, triangle P", or ""
};

// A ray whose final hit changes: batch, index in the emulator's batch, each side's hit (closest
// hits: the primitive, kNoPrim for a miss; shadow rays: 1 occluded, 0 lit) and the verdict.
struct ChangedRay {
  std::string batch;
  std::size_t ray = 0;
  std::uint32_t emu = 0, vulkan = 0;
  bool same_ray = true;  // both sides traced the same ray (else an earlier change moved it)
  std::string verdict;
};

struct DiffImpact {
  std::string actual = "vulkan";      // the actual side's backend, as its passes name it (vulkan, sim)
  std::string failed;                 // why a side's frame could not be made, or ""
  std::size_t rays = 0;               // rays traced by the emulator's frame
  std::size_t rays_changed = 0;       // matched rays whose final hit changes, plus rays on one side only
  std::size_t one_side_only = 0;      // rays traced by one side only
  std::size_t primary_changed = 0;    // pixels whose raster primitive changes
  std::size_t pixels_changed = 0;     // pixels of the final image that change
  std::size_t judged = 0;             // changed rays the exact oracle judged
  std::map<std::string, std::size_t> verdicts;  // emulator, vulkan (the actual side), both, within_rounding, neither
  std::vector<ChangedRay> first;      // the first few changed rays
  std::vector<std::string> differed;  // the first divergent call's differing buffers (BufferComparison::Summary)
  LostTests tests;
  // No ray's final hit and no pixel changes in this frame. Not "benign": what differed (a lost
  // candidate pair, a wrong count) may decide a hit in another frame, and nothing here proves otherwise.
  bool NoVisibleChange() const { return failed.empty() && rays_changed == 0 && primary_changed == 0 && pixels_changed == 0; }
};

// Renders the frame on each side alone and compares (progress on stderr as fo.progress says).
DiffImpact MeasureImpact(const Scene& scene, const SceneBuffers& buffers, emu::FrameOptions fo, const ImpactTracerFactory& tracer,
                         ImpactSide emu_side, ImpactSide vulkan_side);

// "impact: ..." lines for the summary.
void PrintImpact(std::FILE* out, const DiffImpact& impact);
nlohmann::json ImpactJson(const DiffImpact& impact);

}  // namespace rayspace::app
