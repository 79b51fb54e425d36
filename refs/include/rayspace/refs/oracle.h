// Compares a frame's traced batches with a second tracer, ray by ray.
#pragma once
#include <string>
#include <vector>

#include <nlohmann/json_fwd.hpp>

#include "rayspace/emu/frame.h"

namespace rayspace::refs {

struct Disagreement {
  std::string batch;
  std::size_t ray = 0;
  // Closest-hit batches: primitive (kNoPrim = miss) and t. Shadow batches: occluded flag in prim.
  std::uint32_t frame_prim = 0, oracle_prim = 0;
  float frame_t = 0, oracle_t = 0;
  std::string note;
  layout::Ray ray_data{};
};

// How far (relative to the coordinates' magnitude) the oracle lets a float tracer's rounding move a
// decision: 2^-20, 16 float ulps, above what the watertight test's translation, shear and products
// round (docs/numerics.md, "The hit convention").
inline constexpr float kRoundingRel = 0x1p-20f;

// How exact arithmetic judges one tracer's answer for one ray: the exact answer (or one side of an
// exact tie, or an occluder met exactly on an edge), an answer a correct float tracer may give
// (within rounding, as the Oracle's lists), or wrong.
enum class Answer { kExact, kWithinRounding, kWrong };
// `prim`: the closest hit's primitive, kNoPrim for a miss.
Answer JudgeClosest(const layout::Ray& ray, std::uint32_t prim, const SceneBuffers& scene);
Answer JudgeOccluded(const layout::Ray& ray, bool occluded, const SceneBuffers& scene);

class Oracle {
 public:
  // `tracer` re-traces; `scene` lets ties be recognised by re-testing both triangles.
  Oracle(Tracer& tracer, const SceneBuffers& scene) : tracer_(tracer), scene_(scene) {}
  void Check(const emu::Batch& batch);
  std::size_t rays_checked() const { return rays_checked_; }
  // A closest hit agrees when both name the same triangle (or both miss) at distances within
  // rounding (kRoundingRel on the vertices and on t, along the ray's angle to the plane).
  // Every disagreement is settled with exact arithmetic (refs/exact.h) and lands in one list: the
  // frame is wrong (a mismatch), the oracle is wrong, a tie (both hit triangles at exactly the same
  // distance, or the only occluder met exactly on an edge), or within rounding: the frame's answer
  // differs from the exact one only on fragile decisions (ExactJudge at kRoundingRel: grazing rays,
  // hits near an edge or an interval end), which a correct float tracer may take either way.
  const std::vector<Disagreement>& mismatches() const { return mismatches_; }
  const std::vector<Disagreement>& oracle_wrong() const { return oracle_wrong_; }
  const std::vector<Disagreement>& ties() const { return ties_; }
  const std::vector<Disagreement>& within_rounding() const { return rounding_; }
  // A frame that departs from exact shadows on purpose (`why`: --closed-models' front-face culling):
  // a shadow ray the frame answers wrongly is counted as changed by it, not as a mismatch.
  void ExpectShadowChanges(const std::string& why) { shadow_changes_why_ = why; }
  const std::vector<Disagreement>& shadow_changes() const { return shadow_changes_; }
  // Lists every mismatch and every oracle error; ties and answers within rounding up to max_listed.
  void Report(nlohmann::json& out, std::size_t max_listed) const;

 private:
  void CheckOccluded(const emu::Batch& batch);
  void CheckSameTriangle(const std::string& batch, std::size_t i, const layout::Ray& ray, std::uint64_t frame,
                         std::uint64_t oracle);

  Tracer& tracer_;
  const SceneBuffers& scene_;
  std::size_t rays_checked_ = 0;
  std::vector<Disagreement> mismatches_, oracle_wrong_, ties_, rounding_, shadow_changes_;
  std::string shadow_changes_why_;
};

}  // namespace rayspace::refs
