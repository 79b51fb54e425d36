// Errors leave the program as values, never as a signal: an exception thrown inside a parallel loop
// reaches the caller (OpenMP would terminate the process), and a failed invariant check throws
// CheckFailure when the CLI asks for it.
#include <doctest/doctest.h>

#include <atomic>
#include <string>

#include "rayspace/emu/backend.h"
#include "rayspace/emu/frame.h"
#include "rayspace/emu/hierarchy.h"
#include "rayspace/emu/output_checks.h"
#include "rayspace/error.h"
#include "rayspace/parallel.h"
#include "test_util.h"

using namespace rayspace;

TEST_CASE("errors: an exception in a parallel loop reaches the caller, under every schedule") {
  rayspace::test::TestSettings settings;
  for (int threads : {1, 2, 4})
    for (std::size_t chunk : {std::size_t{0}, std::size_t{1}, std::size_t{7}}) {
      CAPTURE(threads);
      CAPTURE(chunk);
      settings->threads = threads;
      settings->chunk = chunk;
      std::atomic<int> ran{0};
      CHECK_THROWS_WITH_AS(ParallelFor(1000, [&](std::size_t i) {
                             ran.fetch_add(1);
                             if (i == 617) ThrowInput("mesh.obj: line {}: bad", i);
                           }),
                           "mesh.obj: line 617: bad", InputError);
      CHECK(ran.load() >= 1);
      CHECK_THROWS_AS(ParallelForDynamic(1000, 16, [&](std::size_t i) {
                        if (i % 100 == 99) throw std::runtime_error("x");
                      }),
                      std::runtime_error);
      // After a failure the pool is usable and complete again.
      std::atomic<int> all{0};
      ParallelFor(1000, [&](std::size_t) { all.fetch_add(1); });
      CHECK(all.load() == 1000);
    }
}

TEST_CASE("errors: a failed check throws CheckFailure naming the condition when asked to") {
  rayspace::test::TestSettings settings;
  settings->check_failures_throw = true;
  settings->threads = 2;
  try {
    ParallelFor(64, [](std::size_t i) { RS_CHECK_MSG(i != 40, "slot {}", i); });
    FAIL("the check did not fire");
  } catch (const CheckFailure& e) {
    const std::string what = e.what();
    CHECK(what.find("i != 40") != std::string::npos);
    CHECK(what.find("slot 40") != std::string::npos);
  }
}

namespace {

// A device whose fused traversal returns one pair outside its block, as a faulty kernel may.
class StrayPairPasses : public emu::ForwardingHierarchyPasses {
 public:
  std::string Name() const override { return "stray"; }
  emu::Compacted TraverseLevelCompacted(const emu::call::TraverseLevelCompacted& c) override {
    emu::Compacted r = ForwardingHierarchyPasses::TraverseLevelCompacted(c);
    if (!r.pairs.empty()) r.pairs.back() = 0x3f800000u;  // 1.0f read as a pair: node 65024
    return r;
  }
};

}  // namespace

TEST_CASE("errors: a pair outside its block from a device stops the frame as a device output error naming the call and level") {
  const Scene s = test::LoadBundled("cornell-mirrors.json");
  const SceneBuffers b = FlattenScene(s);
  StrayPairPasses stray;
  emu::HierarchyConfig hc;
  hc.passes = &stray;
  hc.fused = true;
  auto tracer = emu::MakeHierarchyTracer(b, hc);
  emu::FrameOptions fo;
  fo.width = fo.height = 32;
  try {
    emu::RenderFrame(s, b, *tracer, fo);
    FAIL("the stray pair was used");
  } catch (const emu::DeviceOutputError& e) {
    const std::string what = e.what();
    INFO(what);
    CHECK(what.find("traverse.compact.level (traverse.compact.L1.") == 0);
    CHECK(what.find("from the stray backend: output 'pairs' element ") != std::string::npos);
    CHECK(what.find("0x3f800000") != std::string::npos);
  }
}
