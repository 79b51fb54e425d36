// traverse.compact (gpu/shaders/traverse_compact.comp): the fused test and compaction against the
// emulator's PassTraverseTopCompacted / PassTraverseLevelCompacted and its workgroup mirror, with and
// without the planted faults, and against the two passes it
// replaces (traverse, then reduce), on the calls of real frames and on random configurations: blocks
// of survivors that straddle workgroups and rounds, workgroup sizes, parts, object masks, empty calls
// and calls without survivors; and every planted fault of the kernel must be seen.
#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "rayspace/emu/backend.h"
#include "rayspace/emu/frame.h"
#include "rayspace/emu/hierarchy.h"
#include "rayspace/emu/intersect.h"
#include "rayspace/emu/workgroup_ops.h"
#include "rayspace/gpu/passes.h"
#include "rayspace/scene.h"
#include "rayspace/workgroup.h"
#include "random_traversal.h"
#include "test_settings.h"

namespace rayspace {
namespace {

using emu::call::TraverseLevel;
using emu::call::TraverseLevelCompacted;
using emu::call::TraverseTop;
using emu::call::TraverseTopCompacted;

std::unique_ptr<gpu_backend::VulkanPasses> MakeGpu(const gpu_backend::Faults& faults = {}, std::uint32_t local_size = 64) {
  std::unique_ptr<gpu_backend::VulkanPasses> gpu;
  const vk::Status st = gpu_backend::VulkanPasses::Create(-1, faults, gpu, local_size);
  INFO("Vulkan: " << st.message);
  REQUIRE(st);  // the build has Vulkan and the bootstrap installs lavapipe
  return gpu;
}

// The call's result on the device (the run must succeed).
template <typename Result, typename C>
Result RunOnGpu(gpu_backend::VulkanPasses& gpu, const C& call) {
  Result out;
  const vk::Status st = gpu.Run(call, out);
  INFO(C::kName << ": " << st.message);
  REQUIRE(st);
  return out;
}

template <typename C>
emu::Compacted OnGpu(gpu_backend::VulkanPasses& gpu, const C& call) {
  return RunOnGpu<emu::Compacted>(gpu, call);
}

// The two passes the fused one replaces, on the device: the traversal's slots, then the scan-based
// stream reduction of its flags and values; tests counted from the slots.
template <typename C>
emu::Compacted TwoPassesOnGpu(gpu_backend::VulkanPasses& gpu, const C& call) {
  const emu::PairSlots slots = RunOnGpu<emu::PairSlots>(gpu, call);
  emu::Compacted r;
  for (std::uint8_t t : slots.tested) r.tested += t;
  const emu::call::Reduce reduce{.reduction = emu::Reduction::kScan, .flags = slots.flags, .values = slots.values};
  const auto pairs = RunOnGpu<std::vector<std::uint32_t>>(gpu, reduce);
  r.pairs.assign(pairs.begin(), pairs.end());
  return r;
}

// "" when equal, else where the two first differ.
std::string Difference(const emu::Compacted& expected, const emu::Compacted& actual) {
  if (expected.tested != actual.tested)
    return "tested: " + std::to_string(expected.tested) + " expected, " + std::to_string(actual.tested) + " actual";
  if (expected.pairs.size() != actual.pairs.size())
    return "pairs: " + std::to_string(expected.pairs.size()) + " expected, " + std::to_string(actual.pairs.size()) + " actual";
  const auto m = std::mismatch(expected.pairs.begin(), expected.pairs.end(), actual.pairs.begin());
  if (m.first == expected.pairs.end()) return "";
  return "pairs[" + std::to_string(m.first - expected.pairs.begin()) + "]: " + std::to_string(*m.first) + " expected, " +
         std::to_string(*m.second) + " actual";
}

// ---- random configurations -------------------------------------------------------------------------

// The shared random calls (tests/random_traversal.h) as this file's compacted calls; `masked`: the
// top level's calls use the object mask.
struct TopCase : test::TopCase {
  bool masked;
  TopCase(std::uint32_t seed, std::size_t nodes, std::size_t tris, std::uint32_t objects, bool masked_, bool far = false)
      : test::TopCase(seed, nodes, tris, objects, far), masked(masked_) {}
  TraverseTopCompacted Call(std::uint32_t t0, std::uint32_t t1, std::uint32_t b0, std::uint32_t b1, float eps = 0.0f) const {
    return TraverseTopCompacted{Top(t0, t1, b0, b1, masked, eps)};
  }
};
struct LevelCase : test::LevelCase {
  using test::LevelCase::LevelCase;
  TraverseLevelCompacted Call(float eps = 0.0f) const { return TraverseLevelCompacted{Level(eps)}; }
};

emu::Compacted Emulated(const TraverseTopCompacted& c) { return emu::EmuHierarchyPasses().TraverseTopCompacted(c); }
emu::Compacted Emulated(const TraverseLevelCompacted& c) { return emu::EmuHierarchyPasses().TraverseLevelCompacted(c); }
// The kernel's workgroups on the emulator (emu/src/traverse_compact_wg.cpp), at wg::LocalSize().
emu::Compacted Mirrored(const TraverseTopCompacted& c) { return emu::TraverseTopCompactedWorkgroups(c); }
emu::Compacted Mirrored(const TraverseLevelCompacted& c) { return emu::TraverseLevelCompactedWorkgroups(c); }

// The Vulkan result of `call` equals the emulator's (its fast path and its workgroup mirror) and that
// of the two passes on the device; returns it.
template <typename C>
emu::Compacted CheckCall(gpu_backend::VulkanPasses& gpu, const C& call) {
  emu::CheckInputs(call);
  const emu::Compacted expected = Emulated(call), got = OnGpu(gpu, call);
  CHECK(Difference(expected, got) == "");
  CHECK(Difference(Mirrored(call), got) == "");
  CHECK(Difference(expected, TwoPassesOnGpu(gpu, call)) == "");
  return got;
}

// The emulator's local size for a test's scope.
struct LocalSizeGuard {
  explicit LocalSizeGuard(std::uint32_t n) : in_force([n](Settings& s) { s.local_size = n; }) {}
  ScopedSettings in_force;
};

}  // namespace

TEST_CASE("traverse.compact: random top-level calls equal the emulator and traverse + reduce at every workgroup size") {
  // 300 rows of 340 triangles: tiles of 8 rows, one round a row from local size 64 on (many at 1 and
  // 7, whose short subgroups read the rows' nodes from memory); rows of 1,300 (wide): several rounds
  // at local size 64 with the nodes shuffled.
  const TopCase plain(7, 300, 340, 5, false), masked(8, 300, 340, 5, true), wide(9, 60, 1300, 4, true);
  for (const std::uint32_t local_size : {64u, 1u, 7u, 256u}) {
    CAPTURE(local_size);
    auto gpu = MakeGpu({}, local_size);
    const LocalSizeGuard mirror_local_size(local_size);
    const emu::Compacted all = CheckCall(*gpu, plain.Call(0, 300, 0, 340));
    // Both answers are common, so blocks hold some survivors and not all.
    CHECK(all.pairs.size() > all.tested / 50);
    CHECK(all.pairs.size() < all.tested - all.tested / 20);
    CHECK(all.tested == 300u * 340u);
    const emu::Compacted culled = CheckCall(*gpu, masked.Call(0, 300, 0, 340));
    CHECK(culled.tested < all.tested);
    CHECK(culled.tested > 0u);
    CheckCall(*gpu, masked.Call(17, 211, 33, 301, 0.05f));  // a sub-block: ids relative to t0 and b0, mask rows from t0
    CheckCall(*gpu, wide.Call(0, 60, 0, 1300));
  }
}

TEST_CASE("traverse.compact: random lower-level calls equal the emulator and traverse + reduce") {
  auto gpu = MakeGpu();
  for (const std::uint32_t children_max : {1u, 4u, 8u, 16u}) {
    CAPTURE(children_max);
    const LevelCase lc(children_max, 400, 3000, children_max);
    const emu::Compacted r = CheckCall(*gpu, lc.Call());
    CHECK(r.pairs.size() > 0u);
    CHECK(r.pairs.size() < r.tested);
    CheckCall(*gpu, lc.Call(0.05f));
  }
  auto gpu7 = MakeGpu({}, 7);
  const LocalSizeGuard mirror_local_size(7);
  CheckCall(*gpu7, LevelCase(99, 300, 2000, 8).Call());
}

TEST_CASE("traverse.compact: lower-level pairs in runs of one parent (the subgroup's shared children), any children_max") {
  // Runs of up to 40 pairs with one parent: most subgroups share their children, some straddle two
  // parents. children_max 12, 40 and 100 do not divide a block (pairs split across blocks); 40 and
  // 100 need chunks of kCompactChunk children. Local size 7: one short subgroup (lavapipe's are 8
  // lanes), never shared; 12: a full subgroup, which may share, beside a short one.
  for (const std::uint32_t local_size : {64u, 7u, 12u}) {
    CAPTURE(local_size);
    auto gpu = MakeGpu({}, local_size);
    const LocalSizeGuard mirror_local_size(local_size);
    for (const std::uint32_t children_max : {8u, 16u, 12u, 40u, 100u}) {
      CAPTURE(children_max);
      const LevelCase lc(children_max + 30, 300, 2500, children_max, false, 40);
      const emu::Compacted r = CheckCall(*gpu, lc.Call());
      CHECK(r.pairs.size() > 0u);
      CHECK(r.pairs.size() < r.tested);
    }
  }
}

TEST_CASE("traverse.compact: empty calls and calls without survivors") {
  auto gpu = MakeGpu();
  const TopCase tc(3, 40, 50, 2, true), far(4, 200, 100, 2, false, true);
  constexpr std::array<std::array<std::uint32_t, 4>, 3> kEmpty = {{{0, 0, 0, 50}, {5, 5, 3, 3}, {0, 40, 7, 7}}};
  for (const auto& [t0, t1, b0, b1] : kEmpty) {
    const emu::Compacted r = CheckCall(*gpu, tc.Call(t0, t1, b0, b1));
    CHECK(r.pairs.empty());
    CHECK(r.tested == 0u);
  }
  const emu::Compacted none = CheckCall(*gpu, far.Call(0, 200, 0, 100));
  CHECK(none.pairs.empty());
  CHECK(none.tested == 200u * 100u);
  std::vector<std::uint8_t> zeros(tc.mask.size(), 0);
  TraverseTopCompacted culled = tc.Call(0, 40, 0, 50);
  culled.object_mask = zeros;  // every test culled by the object mask
  const emu::Compacted masked = CheckCall(*gpu, culled);
  CHECK(masked.pairs.empty());
  CHECK(masked.tested == 0u);
  LevelCase lc(5, 50, 100, 8);
  TraverseLevelCompacted no_pairs = lc.Call();
  no_pairs.pairs = {};
  CHECK(CheckCall(*gpu, no_pairs).tested == 0u);
  const LevelCase childless(6, 50, 100, 0), far_level(7, 60, 500, 8, true);
  CHECK(CheckCall(*gpu, childless.Call()).tested == 0u);
  const emu::Compacted far_r = CheckCall(*gpu, far_level.Call());
  CHECK(far_r.pairs.empty());
  CHECK(far_r.tested > 0u);
}

TEST_CASE("traverse.compact: calls split into parts by a small binding limit concatenate in slot order") {
  auto gpu = MakeGpu();
  gpu->LimitForTesting(16384, 3);  // 4,096 words a binding (one block), 3 workgroups a launch row
  const TopCase tc(12, 120, 500, 4, true);
  const std::size_t extra = gpu->extra_dispatches();
  CheckCall(*gpu, tc.Call(0, 120, 0, 500));
  CHECK(gpu->extra_dispatches() - extra >= 10);  // 8 rows of 500 slots a part
  CheckCall(*gpu, LevelCase(13, 150, 4000, 8).Call());  // parts of 512 pairs
}

TEST_CASE("traverse.compact: every planted fault of the kernel is seen, and is the mirror's fault of that number") {
  rayspace::test::TestSettings settings;
  // Rows of 1,200 triangles: several rounds of the top phase at the default local size (fault 3).
  const TopCase tc(21, 300, 1200, 3, false);
  // With the object mask, 7 objects over 1,200 triangles: some invocations' 8 triangles straddle two
  // objects (fault 7 is in the object word of such an invocation).
  const TopCase objects(23, 300, 1200, 7, true);
  // Pairs in runs of one parent, as a level's survivors come (fault 6 is in the subgroups that share them).
  const LevelCase lc(22, 400, 3000, 8, false, 12);
  const TraverseTopCompacted top = tc.Call(0, 300, 0, 1200), masked = objects.Call(0, 300, 0, 1200);
  const emu::Compacted expected = Emulated(top), expected_masked = Emulated(masked);
  for (const FaultSpec& f : Pass(PassId::kTraverseCompact).faults) {
    CAPTURE(f.effect);
    auto gpu = MakeGpu({{"traverse.compact", f.number}});
    emu::Compacted faulty = OnGpu(*gpu, top), faulty_level = OnGpu(*gpu, lc.Call()), faulty_masked = OnGpu(*gpu, masked);
    // Fault 5 is in the top level's group cull (the levels below do not cull), fault 6 in the levels'
    // shared children (the top level shares rows, not children), fault 7 in the top level's object
    // words (seen only with the object mask).
    if (f.number != 6u) CHECK(Difference(f.number == 7u ? expected_masked : expected, f.number == 7u ? faulty_masked : faulty) != "");
    if (f.number != 5u && f.number != 7u) CHECK(Difference(Emulated(lc.Call()), faulty_level) != "");
    // The same fault planted in the emulator's mirror (@emu) is the same mistake, bit for bit, the
    // words it leaves unwritten included (the poison word on both sides).
    settings->emu_faults = {{"traverse.compact", f.number}};
    const emu::Compacted mirrored = Mirrored(top), mirrored_level = Mirrored(lc.Call()), mirrored_masked = Mirrored(masked);
    settings->emu_faults = {};
    if (f.number == 1u) {
      // Fault 1's blocks overlap: block g writes over the start of block g + 1, and which of the two
      // writes a word last depends on the order the workgroups run in, on the device and in the
      // mirror (whose workgroups run on threads) alike. So: the mirror's pairs are wrong too, and
      // the counts, which do not depend on the order, agree.
      CHECK(Difference(expected, mirrored) != "");
      CHECK(Difference(Emulated(lc.Call()), mirrored_level) != "");
      CHECK((mirrored.pairs.size() == faulty.pairs.size() && mirrored.tested == faulty.tested));
      CHECK((mirrored_level.pairs.size() == faulty_level.pairs.size() && mirrored_level.tested == faulty_level.tested));
      continue;
    }
    CHECK(Difference(mirrored, faulty) == "");
    CHECK(Difference(mirrored_level, faulty_level) == "");
    CHECK(Difference(mirrored_masked, faulty_masked) == "");
  }
}

// ---- the calls of real frames --------------------------------------------------------------------

namespace {

// The emulator's hierarchy passes, checking every traversal call of the frame as traverse.compact on
// the device against the emulator's fused result and against the emulator's own slots reduced.
class CompactChecker final : public emu::ForwardingHierarchyPasses {
 public:
  explicit CompactChecker(gpu_backend::VulkanPasses& gpu) : gpu_(gpu) {}
  emu::PairSlots TraverseTop(const emu::call::TraverseTop& c) override {
    return Checked(emu::call::TraverseTopCompacted{c}, ForwardingHierarchyPasses::TraverseTop(c));
  }
  emu::PairSlots TraverseLevel(const emu::call::TraverseLevel& c) override {
    return Checked(emu::call::TraverseLevelCompacted{c}, ForwardingHierarchyPasses::TraverseLevel(c));
  }
  std::size_t calls = 0, pairs = 0, mismatches = 0;

 private:
  // The pass's slots, after checking the compacted call of the same inputs against them.
  template <typename Compacted>
  emu::PairSlots Checked(const Compacted& cc, emu::PairSlots s) {
    Check(cc, s);
    return s;
  }
  template <typename C>
  void Check(const C& c, const emu::PairSlots& s) {
    emu::Compacted two;
    const std::vector<std::uint32_t> reduced = emu::ReduceScan(s.flags, s.values);
    two.pairs.assign(reduced.begin(), reduced.end());
    for (std::uint8_t t : s.tested) two.tested += t;
    const emu::Compacted got = OnGpu(gpu_, c);
    const std::string d = Difference(Emulated(c), got), d2 = Difference(two, got);
    if (!d.empty() || !d2.empty()) {
      ++mismatches;
      MESSAGE(c.kName << ": " << d << " / against traverse + reduce: " << d2);
    }
    ++calls;
    pairs += got.pairs.size();
  }
  gpu_backend::VulkanPasses& gpu_;
};

// What a frame's traversal calls gave: how many ran, their pairs, and how many differed.
struct FrameCheck {
  std::size_t calls = 0, pairs = 0, mismatches = 0;
};

FrameCheck CheckFrame(const std::string& file, int size, emu::Algorithm algorithm) {
  LoadOptions lo;
  lo.data_root = RAYSPACE_TEST_DATA_ROOT;
  const Scene scene = LoadScene(std::filesystem::path(RAYSPACE_SOURCE_DIR) / "scenes" / file, lo);
  const SceneBuffers b = FlattenScene(scene);
  auto gpu = MakeGpu();
  CompactChecker checker(*gpu);
  emu::HierarchyConfig cfg;
  cfg.algorithm = algorithm;
  cfg.image_width = cfg.image_height = size;
  cfg.passes = &checker;
  auto tracer = emu::MakeHierarchyTracer(b, cfg);
  emu::FrameOptions fo;
  fo.width = fo.height = size;
  emu::RenderFrame(scene, b, *tracer, fo);
  return {checker.calls, checker.pairs, checker.mismatches};
}

// Enough calls and pairs for the comparison to mean something.
bool Meaningful(const FrameCheck& f) { return f.calls > 4u && f.pairs > 1000u; }

}  // namespace

TEST_CASE("traverse.compact: every traversal call of cornell-mirrors and office frames") {
  const FrameCheck cornell = CheckFrame("cornell-mirrors.json", 64, emu::Algorithm::kCrsh);
  const FrameCheck office = CheckFrame("office.json", 48, emu::Algorithm::kCrsh);
  const FrameCheck rah = CheckFrame("cornell-mirrors.json", 48, emu::Algorithm::kRah);
  for (const FrameCheck& f : {cornell, office, rah}) {
    CHECK(f.mismatches == 0u);
    CHECK(Meaningful(f));
  }
}

TEST_CASE("traverse.compact: every traversal call of a Sponza frame") {
  if (!std::filesystem::exists(std::filesystem::path(RAYSPACE_TEST_DATA_ROOT) / "sponza_dabrovic" / "sponza.obj")) {
    // ctest counts the case as skipped on this line (SKIP_REGULAR_EXPRESSION in tests/CMakeLists.txt).
    std::printf("data root not found: %s (no sponza_dabrovic/sponza.obj): skipped\n", RAYSPACE_TEST_DATA_ROOT);
    return;
  }
  const FrameCheck sponza = CheckFrame("sponza.json", 32, emu::Algorithm::kCrsh);
  CHECK(sponza.mismatches == 0u);
  CHECK(Meaningful(sponza));
}

}  // namespace rayspace
