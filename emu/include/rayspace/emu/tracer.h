// Tracers answer batches of secondary rays. The emulator's direct tracer and the Embree oracle both
// implement this interface, so a frame can be traced by either and checked by the other.
#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "rayspace/layout.h"
#include "rayspace/digest.h"
#include "rayspace/scene_buffers.h"

namespace rayspace {

// Rules every tracer follows (so that answers are comparable):
// - a ray hits triangle p at t when tmin < t < tmax (origin_tmin.w, direction_tmax.w) and p != info.y;
// - closest hit: smallest t, ties to the lower primitive id, packed with emu::PackHit (miss = ~0);
// - shadow rays: occluded = 1 if any such hit exists.
// What the frame tells a tracer before each batch: names for its statistics and sub-pass timings,
// and the frame's digest log for the buffers its own passes write.
struct SubPass {
  std::string name;
  double ms = 0.0;
  std::size_t elements = 0;
};
struct BatchContext {
  std::string name;  // e.g. "shadow.b0"
  std::uint32_t kind = 0;
  int bounce = 0;
  DigestLog* digest = nullptr;
  std::vector<SubPass>* subpasses = nullptr;
  const layout::FrameConstants* frame = nullptr;  // the frame's constants (eye rays' cells)
};

class Tracer {
 public:
  virtual ~Tracer() = default;
  // Called once after the prep pass with its bounding spheres (kept alive for the frame).
  virtual void Prepare(const std::vector<glm::vec4>& /*triangle_spheres*/, const std::vector<glm::vec4>& /*object_spheres*/) {}
  virtual void BeginBatch(const BatchContext&) {}
  virtual std::string Name() const = 0;
  // Describes the configuration (ISA, build quality, ...) for reports.
  virtual void Describe(nlohmann::json& out) const = 0;
  virtual void Closest(const std::vector<layout::Ray>& rays, std::vector<std::uint64_t>& hits) = 0;
  virtual void Occluded(const std::vector<layout::Ray>& rays, std::vector<std::uint32_t>& occluded) = 0;
};

namespace emu {

enum class DirectMode { kAuto, kExhaustive, kBvh };

// The emulator's direct tracer: every ray against every triangle (exhaustive) for small scenes, a
// bounding-volume hierarchy with conservative box tests for big ones; both give identical answers.
std::unique_ptr<Tracer> MakeDirectTracer(const SceneBuffers& scene, DirectMode mode);

// Scenes up to this many triangles are traced exhaustively in kAuto mode.
inline constexpr std::size_t kExhaustiveMaxTriangles = 256;

}  // namespace emu
}  // namespace rayspace
