// The traversal lists' relaxed device models (verify/src/spec_tl*.cpp): what a conformant device's
// walk of a list, or its window of one, may be, on the smallest lists where the answer follows by hand.
#include <doctest/doctest.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <vector>

#include "rayspace/emu/calls.h"
#include "rayspace/emu/intersect.h"
#include "rayspace/emu/tl/heads.h"
#include "rayspace/emu/tl/layout.h"
#include "rayspace/emu/tl/tl.h"
#include "rayspace/verify/call_codec.h"
#include "rayspace/verify/spec_model.h"

namespace {

using namespace rayspace;

glm::uvec4 SphereWord(glm::vec4 s) {
  return {std::bit_cast<std::uint32_t>(s.x), std::bit_cast<std::uint32_t>(s.y), std::bit_cast<std::uint32_t>(s.z),
          std::bit_cast<std::uint32_t>(s.w)};
}

// One list: a sphere (escape -1: skipping it ends the walk) over two triangles across the ray, at
// z = 5 (id 0) and z = 10 (id 1). The ray runs from the origin along +z up to t = 100.
struct TlCase {
  std::vector<std::uint32_t> first = {0, 3};
  std::vector<std::uint32_t> escapes = {static_cast<std::uint32_t>(emu::tl::kEscapeNone), 1u,
                                        static_cast<std::uint32_t>(emu::tl::kEscapeLast)};
  std::vector<glm::uvec4> words;
  std::vector<glm::vec4> vertices = {{-1, -1, 5, 0}, {1, -1, 5, 0}, {0, 1, 5, 0}, {-1, -1, 10, 0}, {1, -1, 10, 0}, {0, 1, 10, 0}};
  std::vector<layout::Ray> rays;
  emu::call::TlTrace call;
  explicit TlCase(glm::vec4 sphere, std::uint32_t shadow = 0) {
    words = {SphereWord(sphere), glm::uvec4(0, 1, 2, 0), glm::uvec4(3, 4, 5, 1)};
    layout::Ray r{};
    r.origin_tmin = glm::vec4(0, 0, 0, 0);
    r.direction_tmax = glm::vec4(0, 0, 1, 100);
    r.info = glm::uvec4(0, ~0u, 0, 0);
    rays = {r};
    call = {.first = first, .escapes = escapes, .words = words, .vertices = vertices, .rays = rays, .shadow = shadow};
  }
  verify::SpecVerdict Verdict(const emu::TlWalks& device) const {
    const emu::TlWalks emulated = emu::PassTlTrace(call);
    return verify::ClassifyWithinSpec("tl.trace", verify::EncodeCall(call), verify::EncodeOutputs(call, &emulated),
                                      verify::EncodeOutputs(call, &device));
  }
};

// The sphere (0.5, 0, 5, r) whose test the walk passes at the smallest float radius: a sphere on the
// boundary of the test, found by bisection as the emulator decides it.
glm::vec4 BoundarySphere() {
  const auto passes = [](float r) {
    return emu::tl::SphereMayHit(glm::vec3(0), glm::vec3(0, 0, 1), 0.0f, 100.0f, glm::vec4(0.5f, 0, 5, r));
  };
  std::uint32_t lo = std::bit_cast<std::uint32_t>(0.0f), hi = std::bit_cast<std::uint32_t>(1.0f);
  REQUIRE(!passes(0.0f));
  REQUIRE(passes(1.0f));
  while (hi - lo > 1) {
    const std::uint32_t mid = lo + (hi - lo) / 2;
    (passes(std::bit_cast<float>(mid)) ? hi : lo) = mid;
  }
  return glm::vec4(0.5f, 0, 5, std::bit_cast<float>(hi));
}

emu::TlWalks Walks(std::uint64_t hit, std::uint32_t spheres, std::uint32_t triangles) {
  emu::TlWalks w;
  w.hits = {hit};
  w.spheres = {spheres};
  w.triangles = {triangles};
  return w;
}

}  // namespace

TEST_CASE("relaxed model: tl.trace's closest hit is a permitted hit of a triangle some walk tests, none surely nearer") {
  const TlCase wide(glm::vec4(0, 0, 7, 100));  // a sphere every device enters
  const emu::TlWalks emulated = emu::PassTlTrace(wide.call);
  REQUIRE(emulated.hits[0] == emu::PackHit(5.0f, 0));
  REQUIRE(emulated.spheres[0] == 1);
  REQUIRE(emulated.triangles[0] == 2);
  const auto next = [](float t) { return std::nextafter(t, 100.0f); };
  const verify::SpecVerdict ulp = wide.Verdict(Walks(emu::PackHit(next(5.0f), 0), 1, 2));  // t = (v0 - o).n / d.n
  CHECK(ulp.modelled);
  CHECK(ulp.within == 1);
  CHECK(ulp.beyond == 0);
  CHECK(wide.Verdict(Walks(emu::PackHit(5.5f, 0), 1, 2)).beyond == 1);    // t far from any permitted quotient
  CHECK(wide.Verdict(Walks(emu::PackHit(10.0f, 1), 1, 2)).beyond == 1);   // the nearer triangle surely tested
  CHECK(wide.Verdict(Walks(emu::kMissPacked, 1, 2)).beyond == 1);         // a miss where a hit is sure
  CHECK(wide.Verdict(Walks(emu::PackHit(5.0f, 7), 1, 2)).beyond == 1);    // no such triangle in the list
  CHECK(wide.Verdict(Walks(emulated.hits[0], 1, 1)).beyond == 1);         // a surely visited triangle not counted
  CHECK(wide.Verdict(Walks(emulated.hits[0], 2, 2)).beyond == 1);         // more spheres than the list holds
}

TEST_CASE("relaxed model: tl.trace may skip a sphere whose test sits on its boundary, not one far from it") {
  const TlCase boundary(BoundarySphere());
  const emu::TlWalks emulated = emu::PassTlTrace(boundary.call);
  REQUIRE(emulated.hits[0] == emu::PackHit(5.0f, 0));  // the sphere entered, both triangles tested
  const verify::SpecVerdict skipped = boundary.Verdict(Walks(emu::kMissPacked, 1, 0));
  CHECK(skipped.modelled);
  CHECK(skipped.within == 1);
  CHECK(skipped.beyond == 0);
  CHECK(boundary.Verdict(Walks(emu::kMissPacked, 1, 3)).beyond == 1);  // more triangles than any walk tests
  CHECK(boundary.Verdict(Walks(emu::PackHit(5.5f, 0), 1, 2)).beyond == 1);  // entered, but no permitted t

  const TlCase far(glm::vec4(0, 0, 7, 100));
  const verify::SpecVerdict dropped = far.Verdict(Walks(emu::kMissPacked, 1, 0));
  CHECK(dropped.beyond == 1);
  CHECK(dropped.first_beyond.find("hits[0]") != std::string::npos);
}

TEST_CASE("relaxed model: a tl.trace shadow ray is occluded only by a triangle some walk may hit") {
  const TlCase wide(glm::vec4(0, 0, 7, 100), 1);
  const emu::TlWalks emulated = emu::PassTlTrace(wide.call);
  REQUIRE(emulated.occluded[0] == 1);
  emu::TlWalks lit = emulated;
  lit.occluded = {0};
  CHECK(wide.Verdict(lit).beyond == 1);  // the sure hit at z = 5 missed
  const TlCase boundary(BoundarySphere(), 1);
  emu::TlWalks skipped = emu::PassTlTrace(boundary.call);
  skipped.occluded = {0};
  skipped.triangles = {0};
  CHECK(boundary.Verdict(skipped).AllWithin());
}

namespace {

// tl.heads' smallest call: one list of two triangle elements, A then C, and the ray's triangle T in
// the plane z = 0 (normal +z, margin 1). Case 0 (rays starting on T, in front) rejects a triangle
// wholly below z = -|n| margin; C lies at z = 1, A at `za`.
struct HeadsCase {
  std::vector<std::uint32_t> first = {0, 2};
  std::vector<std::uint32_t> escapes = {1u, static_cast<std::uint32_t>(emu::tl::kEscapeLast)};
  std::vector<glm::uvec4> words = {glm::uvec4(3, 4, 5, 1), glm::uvec4(6, 7, 8, 2)};
  std::vector<glm::uvec4> tri_words = {glm::uvec4(0, 1, 2, 0), glm::uvec4(3, 4, 5, 1), glm::uvec4(6, 7, 8, 2)};
  std::vector<glm::vec4> vertices;
  emu::call::TlHeads call;
  explicit HeadsCase(float za) {
    vertices = {{0, 0, 0, 1}, {1, 0, 0, 1}, {0, 1, 0, 1}, {0, 0, za, 1}, {1, 0, za, 1}, {0, 1, za, 1}, {0, 0, 1, 1}, {1, 0, 1, 1}, {0, 1, 1, 1}};
    call = {.first = first, .escapes = escapes, .words = words, .vertices = vertices, .tri_words = tri_words,
            .mode = layout::kTlHeadsSimple, .margin = 1.0f};
  }
  // The verdict on a device whose window of (T, case 0, the list) is [head, tail).
  verify::SpecVerdict Verdict(std::uint32_t head, std::uint32_t tail) const {
    const emu::TlWindows emulated = emu::PassTlHeads(call);
    emu::TlWindows device = emulated;
    device.windows[0] = head;
    device.windows[1] = tail;
    return verify::ClassifyWithinSpec("tl.heads", verify::EncodeCall(call), verify::EncodeOutputs(call, &emulated),
                                      verify::EncodeOutputs(call, &device));
  }
};

}  // namespace

TEST_CASE("relaxed model: a tl.heads window may keep a triangle on the margin's boundary, not one far beyond it") {
  const HeadsCase boundary(std::nextafter(-1.0f, -2.0f));  // rejected by the emulator, by |n| = sqrt(1) rounded up not
  REQUIRE(emu::PassTlHeads(boundary.call).windows[0] == 1u);
  REQUIRE(emu::PassTlHeads(boundary.call).windows[1] == 2u);
  const verify::SpecVerdict kept = boundary.Verdict(0, 2);
  CHECK(kept.modelled);
  CHECK(kept.within == 1);
  CHECK(kept.beyond == 0);
  CHECK(boundary.Verdict(0, 1).beyond == 1);  // C, which no device rejects, left out
  CHECK(boundary.Verdict(1, 1).beyond == 1);  // empty, though C is in every device's window
  const HeadsCase far(-2.0f);
  REQUIRE(emu::PassTlHeads(far.call).windows[0] == 1u);
  const verify::SpecVerdict wider = far.Verdict(0, 2);
  CHECK(wider.beyond == 1);
  CHECK(wider.first_beyond.find("windows[0]") != std::string::npos);
}
