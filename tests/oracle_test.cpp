// The Embree oracle agrees with the emulated frame on the bundled scenes (at reduced size), and the
// comparison catches a planted wrong answer.
#include <doctest/doctest.h>

#include <functional>

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
  if (test::SkipWithoutData("sponza_dabrovic/sponza.obj")) return;
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
  FlipOne(Tracer& inner, const SceneBuffers&, std::size_t ray = 123) : inner_(inner), ray_(ray) {}
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

// Renders cornell-mirrors at 32x32 with a faulty frame tracer wrapped around the direct tracer and
// checks it with the Embree oracle; `inspect` sees the oracle and the faulty tracer afterwards.
template <typename Fault>
void RunWithFault(const std::function<void(const refs::Oracle&, const Fault&)>& inspect) {
  const Scene s = test::LoadBundled("cornell-mirrors.json");
  const SceneBuffers b = FlattenScene(s);
  auto direct = emu::MakeDirectTracer(b, emu::DirectMode::kAuto);
  Fault faulty(*direct, b);
  auto embree = refs::MakeEmbreeTracer(b, 0);
  refs::Oracle oracle(*embree, b);
  emu::FrameOptions fo;
  fo.width = 32;
  fo.height = 32;
  emu::RenderFrame(s, b, faulty, fo, [&](const emu::Batch& batch) { oracle.Check(batch); });
  inspect(oracle, faulty);
}

TEST_CASE("planted fault: a tracer that flips one answer is reported as a mismatch on that ray") {
  RunWithFault<FlipOne>([](const refs::Oracle& oracle, const FlipOne&) {
    REQUIRE(!oracle.mismatches().empty());
    for (const auto& m : oracle.mismatches()) CHECK(m.ray == 123);
    CHECK(oracle.oracle_wrong().empty());
  });
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

namespace {

// A tracer that answers like another but reports the second-nearest triangle the emulator's test
// accepts in place of the nearest for one ray (hit/miss unchanged): a planted fault the hit/miss
// comparison alone would not see.
class SwapOne final : public Tracer {
 public:
  SwapOne(Tracer& inner, const SceneBuffers& scene) : inner_(inner), scene_(scene) {}
  std::string Name() const override { return "swap-one"; }
  void Describe(nlohmann::json& out) const override { inner_.Describe(out); }
  void Closest(const std::vector<layout::Ray>& rays, std::vector<std::uint64_t>& hits) override {
    inner_.Closest(rays, hits);
    for (std::size_t i = 0; i < rays.size() && swapped_ == SIZE_MAX; ++i) {
      if (hits[i] == emu::kMissPacked) continue;
      const std::uint64_t second = SecondNearest(rays[i], hits[i]);
      if (second == emu::kMissPacked) continue;
      hits[i] = second;
      swapped_ = i;
    }
  }
  void Occluded(const std::vector<layout::Ray>& rays, std::vector<std::uint32_t>& occ) override { inner_.Occluded(rays, occ); }
  std::size_t swapped() const { return swapped_; }

 private:
  // The nearest hit farther than `first` by more than rounding could explain (a thousandth of t).
  std::uint64_t SecondNearest(const layout::Ray& r, std::uint64_t first) const {
    const emu::WatertightRay wr = emu::SetupWatertight(emu::Xyz(r.origin_tmin), emu::Xyz(r.direction_tmax));
    std::uint64_t best = emu::kMissPacked;
    for (std::uint32_t p = 0; p < scene_.triangles.size(); ++p) {
      const layout::Triangle& t = scene_.triangles[p];
      float th;
      if (p == r.info.y || !emu::IntersectWatertight(wr, emu::Xyz(t.v0), emu::Xyz(t.v1), emu::Xyz(t.v2), r.origin_tmin.w,
                                                      r.direction_tmax.w, th))
        continue;
      if (th > emu::HitT(first) * 1.001f) best = std::min(best, emu::PackHit(th, p));
    }
    return best;
  }

  Tracer& inner_;
  const SceneBuffers& scene_;
  std::size_t swapped_ = SIZE_MAX;
};

// One shadow ray of the dragon close-up (512x512, light at (8, 20, 14)) and the two dragon triangles
// it crosses just before its end: the light lies almost in their plane, so the ray grazes them, and
// in exact arithmetic it passes through both interiors near their shared edge; the watertight test
// misses both. Triangle 0 is the surface the ray ends on (info.y), triangle 1 its neighbour.
struct GrazingShadow {
  SceneBuffers scene;
  layout::Ray ray{};
  GrazingShadow() {
    scene.triangles.resize(2);
    scene.triangles[0].v0 = {-0x1.0c5c82p+2f, 0x1.86594ap-2f, 0x1.ceac52p+0f, 1};
    scene.triangles[0].v1 = {-0x1.fe48b4p+1f, 0x1.5cc64p-2f, 0x1.d4e402p+0f, 1};
    scene.triangles[0].v2 = {-0x1.067dacp+2f, 0x1.de00d2p-2f, 0x1.de666cp+0f, 1};
    scene.triangles[1].v0 = {-0x1.02e03ap+2f, 0x1.167a1p-1f, 0x1.e99db4p+0f, 1};
    scene.triangles[1].v1 = scene.triangles[0].v2;
    scene.triangles[1].v2 = scene.triangles[0].v1;
    ray.origin_tmin = {8, 20, 14, 0x1.c64eb2p-14f};
    ray.direction_tmax = {-0x1.d9f26p-2f, -0x1.81beb2p-1f, -0x1.de484p-2f, 0x1.a04ceap+4f};
    ray.info = glm::uvec4(0, 0, layout::kRayShadow, 0);
  }
};

}  // namespace

TEST_CASE("oracle: a grazing shadow ray the float test calls lit is within rounding, not a mismatch") {
  GrazingShadow g;
  REQUIRE(refs::ExactOccluded(g.ray, g.scene) == refs::Contact::kInterior);
  const refs::Judgement j = refs::ExactJudge(g.ray, g.scene.triangles[1], refs::kRoundingRel);
  CHECK(j.hit);
  CHECK_FALSE(j.robust);
  float t;
  const layout::Triangle& n = g.scene.triangles[1];
  CHECK_FALSE(emu::IntersectWatertight(emu::SetupWatertight(emu::Xyz(g.ray.origin_tmin), emu::Xyz(g.ray.direction_tmax)),
                                       emu::Xyz(n.v0), emu::Xyz(n.v1), emu::Xyz(n.v2), g.ray.origin_tmin.w,
                                       g.ray.direction_tmax.w, t));
  auto embree = refs::MakeEmbreeTracer(g.scene, 1);
  const std::vector<layout::Ray> rays{g.ray};
  const std::vector<std::uint32_t> lit{0u};
  emu::Batch batch{"shadow.b0", layout::kRayShadow, 0, &rays, nullptr, &lit};
  refs::Oracle oracle(*embree, g.scene);
  oracle.Check(batch);
  CHECK(oracle.mismatches().empty());
  CHECK(oracle.within_rounding().size() + oracle.oracle_wrong().size() == 1);

  // A ray along the neighbour's normal through its centroid crosses it robustly: "lit" is a mismatch.
  const glm::vec3 c = (emu::Xyz(n.v0) + emu::Xyz(n.v1) + emu::Xyz(n.v2)) / 3.0f;
  const glm::vec3 nn = glm::normalize(glm::cross(emu::Xyz(n.v1) - emu::Xyz(n.v0), emu::Xyz(n.v2) - emu::Xyz(n.v0)));
  std::vector<layout::Ray> across{g.ray};
  across[0].origin_tmin = glm::vec4(c + 3.0f * nn, g.ray.origin_tmin.w);
  across[0].direction_tmax = glm::vec4(-nn, 6.0f);
  CHECK(refs::ExactJudge(across[0], n, refs::kRoundingRel).robust);
  refs::Oracle strict(*embree, g.scene);
  strict.Check(emu::Batch{"shadow.b0", layout::kRayShadow, 0, &across, nullptr, &lit});
  CHECK(strict.mismatches().size() == 1);
  CHECK(strict.within_rounding().empty());
}

TEST_CASE("planted fault: a tracer that reports another triangle for one ray is a mismatch on that ray") {
  RunWithFault<SwapOne>([](const refs::Oracle& oracle, const SwapOne& faulty) {
    REQUIRE(faulty.swapped() != SIZE_MAX);
    REQUIRE(oracle.mismatches().size() >= 1);
    for (const auto& m : oracle.mismatches()) CHECK(m.frame_prim != m.oracle_prim);
    CHECK(oracle.within_rounding().empty());
  });
}

namespace {

// A tracer that answers like another but puts one ray's hit 1% farther along the ray, on the same
// triangle: a planted fault that comparing triangles alone would not see.
class StretchOne final : public Tracer {
 public:
  StretchOne(Tracer& inner, const SceneBuffers&) : inner_(inner) {}
  std::string Name() const override { return "stretch-one"; }
  void Describe(nlohmann::json& out) const override { inner_.Describe(out); }
  void Closest(const std::vector<layout::Ray>& rays, std::vector<std::uint64_t>& hits) override {
    inner_.Closest(rays, hits);
    for (std::size_t i = 0; i < rays.size() && stretched_ == SIZE_MAX; ++i) {
      if (hits[i] == emu::kMissPacked) continue;
      hits[i] = emu::PackHit(emu::HitT(hits[i]) * 1.01f, emu::HitPrim(hits[i]));
      stretched_ = i;
    }
  }
  void Occluded(const std::vector<layout::Ray>& rays, std::vector<std::uint32_t>& occ) override { inner_.Occluded(rays, occ); }
  std::size_t stretched() const { return stretched_; }

 private:
  Tracer& inner_;
  std::size_t stretched_ = SIZE_MAX;
};

}  // namespace

TEST_CASE("planted fault: a tracer that reports the right triangle at the wrong distance is a mismatch on that ray") {
  RunWithFault<StretchOne>([](const refs::Oracle& oracle, const StretchOne& faulty) {
    REQUIRE(faulty.stretched() != SIZE_MAX);
    REQUIRE(oracle.mismatches().size() == 1);
    const refs::Disagreement& m = oracle.mismatches().front();
    CHECK(m.ray == faulty.stretched());
    CHECK(m.frame_prim == m.oracle_prim);
    CHECK(m.frame_t == doctest::Approx(m.oracle_t * 1.01f).epsilon(1e-5));
    CHECK(oracle.oracle_wrong().empty());
  });
}

TEST_CASE("embree: the BVH is built before the first batch, timed once as the sub-pass embree.build; an oracle's query builds it too") {
  const Scene s = test::LoadBundled("cornell-mirrors.json");
  const SceneBuffers b = FlattenScene(s);
  auto tracer = refs::MakeEmbreeTracer(b, 0);
  emu::FrameOptions fo;
  fo.width = fo.height = 16;
  const emu::FrameResult r = emu::RenderFrame(s, b, *tracer, fo);
  int builds = 0;
  std::string first_trace;
  for (const emu::PassRecord& p : r.passes) {
    if (first_trace.empty() && p.name.rfind("trace.", 0) == 0 && p.ran) first_trace = p.name;
    if (p.name != "embree.build") continue;
    ++builds;
    CHECK(p.ran);
    CHECK(p.elements == b.triangles.size());
    CHECK(first_trace.empty());  // listed before the batch that ran it, as every sub-pass
  }
  CHECK(builds == 1);
  // Without a frame (the oracle's use): the first query builds the BVH and answers.
  auto oracle = refs::MakeEmbreeTracer(b, 0);
  std::vector<std::uint32_t> occluded;
  oracle->Occluded({test::MakeRay({0, 0, 0}, {0, 1, 0})}, occluded);
  CHECK(occluded.size() == 1);
}
