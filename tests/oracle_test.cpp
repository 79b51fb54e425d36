// The Embree oracle agrees with the emulated frame on the bundled scenes (at reduced size), and the
// comparison catches a planted wrong answer.
#include <doctest/doctest.h>

#include "rayspace/emu/frame.h"
#include "rayspace/emu/intersect.h"
#include "rayspace/refs/embree_tracer.h"
#include "rayspace/refs/exact.h"
#include "rayspace/refs/oracle.h"
#include "test_util.h"

using namespace rayspace;

namespace {

struct OracleRun {
  std::size_t checked = 0, mismatches = 0, oracle_wrong = 0;
  std::uint64_t digest = 0;
  emu::FrameResult frame;
};

OracleRun Check(const Scene& s, int w, int h, bool embree_frames, emu::DirectMode mode = emu::DirectMode::kAuto) {
  const SceneBuffers b = FlattenScene(s);
  auto direct = emu::MakeDirectTracer(b, mode);
  auto embree = refs::MakeEmbreeTracer(b, 0);
  Tracer& frame_tracer = embree_frames ? *embree : *direct;
  refs::Oracle oracle(embree_frames ? *direct : *embree, b);
  emu::FrameOptions fo;
  fo.width = w;
  fo.height = h;
  OracleRun r;
  r.frame = emu::RenderFrame(s, b, frame_tracer, fo, [&](const emu::Batch& batch) { oracle.Check(batch); });
  r.checked = oracle.rays_checked();
  r.mismatches = oracle.mismatches().size();
  r.oracle_wrong = oracle.oracle_wrong().size();
  r.digest = r.frame.digest.Frame();
  for (const auto& m : oracle.mismatches()) MESSAGE(m.batch << " ray " << m.ray << ": " << m.note);
  return r;
}

}  // namespace

TEST_CASE("oracle: cornell-mirrors agrees with Embree ray by ray") {
  const Scene s = test::LoadBundled("cornell-mirrors.json");
  const OracleRun r = Check(s, 96, 96, false);
  CHECK(r.checked > 96 * 96 * 3);
  CHECK(r.mismatches == 0);
  CHECK(r.frame.rays[layout::kRayReflection].size() == 3);
  CHECK(r.frame.rays[layout::kRayReflection][1] > 0);
  CHECK(r.frame.rays[layout::kRayReflection][2] > 0);
  // Frames traced by Embree, checked by the emulator's tracer.
  CHECK(Check(s, 64, 64, true).mismatches == 0);
}

TEST_CASE("oracle: office agrees with Embree") {
  const Scene s = test::LoadBundled("office.json");
  const OracleRun r = Check(s, 64, 64, false);
  CHECK(r.checked >= 64 * 64 / 2);
  CHECK(r.mismatches == 0);
}

TEST_CASE("oracle: sponza agrees with Embree, and BVH equals exhaustive tracing") {
  if (!test::HaveData()) {
    MESSAGE("data root " << test::DataRoot() << " not found; skipping Sponza");
    return;
  }
  const Scene s = test::LoadBundled("sponza.json");
  const OracleRun r = Check(s, 48, 48, false, emu::DirectMode::kBvh);
  CHECK(r.checked > 48 * 48 / 2);
  CHECK(r.mismatches == 0);
  const OracleRun ex = Check(s, 48, 48, false, emu::DirectMode::kExhaustive);
  CHECK(ex.digest == r.digest);
}

namespace {

// A tracer that answers like another but flips one ray's answer: a planted fault.
class FlipOne final : public Tracer {
 public:
  FlipOne(Tracer& inner, std::size_t ray) : inner_(inner), ray_(ray) {}
  std::string Name() const override { return "flip-one"; }
  void Describe(nlohmann::json& out) const override { inner_.Describe(out); }
  void Closest(const std::vector<layout::Ray>& rays, std::vector<std::uint64_t>& hits) override {
    inner_.Closest(rays, hits);
    if (ray_ < hits.size()) hits[ray_] = hits[ray_] == emu::kMissPacked ? emu::PackHit(1.0f, 0) : emu::kMissPacked;
  }
  void Occluded(const std::vector<layout::Ray>& rays, std::vector<std::uint32_t>& occ) override {
    inner_.Occluded(rays, occ);
    if (ray_ < occ.size()) occ[ray_] ^= 1u;
  }

 private:
  Tracer& inner_;
  std::size_t ray_;
};

}  // namespace

TEST_CASE("planted fault: a tracer that flips one answer is reported as a mismatch on that ray") {
  const Scene s = test::LoadBundled("cornell-mirrors.json");
  const SceneBuffers b = FlattenScene(s);
  auto direct = emu::MakeDirectTracer(b, emu::DirectMode::kAuto);
  FlipOne faulty(*direct, 123);
  auto embree = refs::MakeEmbreeTracer(b, 0);
  refs::Oracle oracle(*embree, b);
  emu::FrameOptions fo;
  fo.width = 32;
  fo.height = 32;
  emu::RenderFrame(s, b, faulty, fo, [&](const emu::Batch& batch) { oracle.Check(batch); });
  REQUIRE(!oracle.mismatches().empty());
  for (const auto& m : oracle.mismatches()) CHECK(m.ray == 123);
  CHECK(oracle.oracle_wrong().empty());
}

TEST_CASE("exact adjudication: a ray just outside a triangle misses exactly") {
  // Sponza's triangle 510 and a shadow ray Embree (sse4.2, robust) reports as hitting it; in exact
  // arithmetic the ray passes outside (barycentric -3.6e-4).
  layout::Triangle t;
  t.v0 = {10.8352003f, -1.18886006f, 4.63565016f, 1};
  t.v1 = {10.8352003f, -0.907504022f, 4.76227999f, 1};
  t.v2 = {10.8472004f, -0.904844999f, 4.75527f, 1};
  layout::Ray r{};
  r.origin_tmin = {0, 0, 14, 0};
  r.direction_tmax = {0.7544096112251282f, -0.0813230574131012f, -0.6513468623161316f, 14.42607593536377f};
  CHECK_FALSE(refs::ExactHits(r, t));
  // Moved onto the triangle's centroid the same ray hits exactly.
  const glm::vec3 c = (emu::Xyz(t.v0) + emu::Xyz(t.v1) + emu::Xyz(t.v2)) / 3.0f;
  r.direction_tmax = glm::vec4(c - glm::vec3(0, 0, 14), 2.0f);
  CHECK(refs::ExactHits(r, t));
  r.direction_tmax.w = 0.999f;  // tmax before the hit
  CHECK_FALSE(refs::ExactHits(r, t));
}
