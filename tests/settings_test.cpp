// Settings are per thread and per scope, never process-wide: frames started on different threads
// with different settings (thread count, schedule, local and subgroup size, the workgroup model, a
// planted fault) give each the frame it gives alone, while they run at the same time.
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <thread>
#include <vector>

#include "rayspace/emu/frame.h"
#include "rayspace/emu/hierarchy.h"
#include "rayspace/error.h"
#include "rayspace/parallel.h"
#include "rayspace/settings.h"
#include "test_util.h"

namespace rayspace {
namespace {

// The frame digest of the bundled Cornell box at 32x32 through the CRSH hierarchy's fused path, with
// `settings` in force for the frame.
std::uint64_t FrameWith(const Settings& settings) {
  const ScopedSettings in_force(settings);
  const Scene s = test::LoadBundled("cornell-mirrors.json");
  const SceneBuffers b = FlattenScene(s);
  emu::HierarchyConfig cfg;
  cfg.fused = true;
  auto tracer = emu::MakeHierarchyTracer(b, cfg);
  emu::FrameOptions fo;
  fo.width = fo.height = 32;
  return emu::RenderFrame(s, b, *tracer, fo).digest.Frame();
}

// Three settings: the defaults on one thread; the workgroup model checked under a random schedule at
// another local and subgroup size (the same frame: the passes do not depend on the schedule); and an
// unsound group cull planted in the fused path (a negative margin: another frame).
std::array<Settings, 3> ThreeSettings() {
  std::array<Settings, 3> s{};
  s[0].threads = 1;
  s[1].threads = 2;
  s[1].chunk = 5;
  s[1].workgroup_model = true;
  s[1].check = true;
  s[1].schedule = {wg::Order::kRandom, 77};
  s[1].local_size = 128;
  s[1].subgroup_size = 16;
  s[2].threads = 2;
  s[2].cull_margin = -0.25;
  return s;
}

TEST_CASE("settings: frames with different settings on concurrent threads give what each gives alone") {
  const std::array<Settings, 3> settings = ThreeSettings();
  std::array<std::uint64_t, 3> alone{};
  for (std::size_t i = 0; i < settings.size(); ++i) alone[i] = FrameWith(settings[i]);
  CHECK(alone[1] == alone[0]);  // schedule, sizes and the model: the same frame
  CHECK(alone[2] != alone[0]);  // the planted cull: another frame
  for (int round = 0; round < 3; ++round) {
    CAPTURE(round);
    std::array<std::uint64_t, 3> together{};
    std::vector<std::thread> threads;
    for (std::size_t i = 0; i < settings.size(); ++i) threads.emplace_back([&, i] { together[i] = FrameWith(settings[i]); });
    for (std::thread& t : threads) t.join();
    CHECK(together == alone);
  }
}

TEST_CASE("settings: a scope's settings end with it, nest, and reach ParallelFor's workers") {
  CHECK(CurrentSettings().threads == 0);
  {
    const ScopedSettings outer([](Settings& s) { s.threads = 2; s.local_size = 32; });
    {
      const ScopedSettings inner([](Settings& s) { s.local_size = 256; });
      CHECK(CurrentSettings().threads == 2);  // inherited from the outer scope
      std::vector<std::uint32_t> seen(64);
      ParallelFor(seen.size(), [&](std::size_t i) { seen[i] = CurrentSettings().local_size; });
      CHECK(std::count(seen.begin(), seen.end(), 256u) == 64);
    }
    CHECK(CurrentSettings().local_size == 32);
  }
  CHECK(CurrentSettings().local_size == 64);
  CHECK(CurrentSettings().threads == 0);
}

TEST_CASE("settings: a subgroup or local size out of range is refused when the scope begins") {
  const ScopedSettings throwing([](Settings& s) { s.check_failures_throw = true; });
  CHECK_THROWS_AS(ScopedSettings([](Settings& s) { s.subgroup_size = 6; }), CheckFailure);
  CHECK_THROWS_AS(ScopedSettings([](Settings& s) { s.local_size = 0; }), CheckFailure);
  CHECK_THROWS_AS(ScopedSettings([](Settings& s) { s.local_size = 2048; }), CheckFailure);
  CHECK(CurrentSettings().local_size == 64);
}

}  // namespace
}  // namespace rayspace
