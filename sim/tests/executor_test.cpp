// Known answers of the executor on small GLSL kernels compiled here with glslc: subgroup operations
// over active lanes, reconvergence after divergent branches and loops, barriers that publish shared
// memory across subgroups, and the faults a run reports (an access outside a binding, a division by
// zero, a barrier part of the workgroup never reaches, a hang), each by its checker, and what the
// kernel does with that checker switched off.
#include <doctest/doctest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "rayspace/error.h"
#include "rayspace/sim/executor.h"
#include "rayspace/sim/program.h"

namespace {

namespace fs = std::filesystem;
namespace sim = rayspace::sim;

std::vector<std::uint32_t> Compile(const std::string& body, const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("rayspace-sim-exec-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const fs::path src = dir / (name + ".comp"), out = dir / (name + ".spv");
  std::ofstream(src) << "#version 460\n#extension GL_KHR_shader_subgroup_basic : require\n"
                        "#extension GL_KHR_shader_subgroup_arithmetic : require\n"
                        "#extension GL_KHR_shader_subgroup_ballot : require\n"
                        "#extension GL_KHR_shader_subgroup_shuffle : require\n"
                        "layout(local_size_x_id = 1) in;\n"
                        "layout(std430, binding = 0) buffer Data { uint data[]; };\n"
                     << body;
  const std::string cmd = std::string(RAYSPACE_TEST_GLSLC) + " -O0 -g --target-env=vulkan1.2 " + src.string() + " -o " + out.string();
  REQUIRE_MESSAGE(std::system(cmd.c_str()) == 0, body);
  std::ifstream in(out, std::ios::binary);
  std::vector<std::uint32_t> words(fs::file_size(out) / 4);
  in.read(reinterpret_cast<char*>(words.data()), static_cast<std::streamsize>(words.size() * 4));
  fs::remove_all(dir);
  return words;
}

// Runs `body` over `groups` workgroups of `local` invocations, subgroups of `subgroup`, on `data`.
std::vector<std::uint32_t> Run(const std::string& body, std::uint32_t local, std::uint32_t groups, std::uint32_t subgroup,
                               std::vector<std::uint32_t> data, rayspace::wg::Schedule schedule = {}, sim::Checks checks = {},
                               sim::DeviceModelChoice arithmetic = {}, sim::SubgroupLayoutChoice layout = {}) {
  const sim::Program p = sim::Prepare(Compile(body, "k"), {{1, std::to_string(local)}}, "k");
  sim::Dispatch d;
  d.arithmetic = arithmetic;
  d.layout = layout;
  d.schedule = schedule;
  d.checks = checks;
  d.groups[0] = groups;
  d.subgroup_size = subgroup;
  d.step_limit = 1u << 24;
  d.bindings.push_back({reinterpret_cast<std::uint8_t*>(data.data()), data.size() * 4});
  sim::ExecStats stats;
  sim::Run(p, d, stats);
  return data;
}

}  // namespace

TEST_CASE("sim executor: subgroup operations see the subgroup's lanes, in lane order") {
  const auto out = Run(R"(void main() {
    uint i = gl_LocalInvocationIndex;
    data[i] = subgroupInclusiveAdd(i);
    data[32 + i] = subgroupExclusiveAdd(1u) + 100u * gl_SubgroupID;
    data[64 + i] = subgroupBallotBitCount(subgroupBallot(i % 3u == 0u)) + (subgroupElect() ? 1000u : 0u);
    data[96 + i] = subgroupShuffle(i * 10u, (gl_SubgroupInvocationID + 1u) % gl_SubgroupSize);
  })", 32, 1, 8, std::vector<std::uint32_t>(128, 0));
  for (std::uint32_t i = 0; i < 32; ++i) {
    const std::uint32_t base = i - i % 8;
    std::uint32_t inclusive = 0, thirds = 0;
    for (std::uint32_t k = base; k <= i; ++k) inclusive += k;
    for (std::uint32_t k = base; k < base + 8; ++k) thirds += k % 3 == 0;
    CHECK(out[i] == inclusive);
    CHECK(out[32 + i] == i % 8 + 100 * (i / 8));
    CHECK(out[64 + i] == thirds + (i % 8 == 0 ? 1000 : 0));
    CHECK(out[96 + i] == (base + (i + 1) % 8) * 10);
  }
}

TEST_CASE("sim executor: lanes that diverge run alone and reconverge after the branch and the loop") {
  const auto out = Run(R"(void main() {
    uint i = gl_LocalInvocationIndex;
    uint inside = 0u;
    if (i % 2u == 0u) inside = subgroupAdd(1u);
    uint after = subgroupAdd(1u);
    uint n = 0u;
    for (uint k = 0u; k < i % 4u; ++k) n += subgroupAdd(1u);
    data[i] = inside;
    data[16 + i] = after;
    data[32 + i] = n;
    data[48 + i] = subgroupAdd(1u);
  })", 16, 1, 8, std::vector<std::uint32_t>(64, 0));
  for (std::uint32_t i = 0; i < 16; ++i) {
    CHECK(out[i] == (i % 2 == 0 ? 4u : 0u));  // the even lanes of eight
    CHECK(out[16 + i] == 8);
    // Iteration k runs with the lanes whose i % 4 > k: 6, 4, then 2 of eight.
    const std::uint32_t want[4] = {0, 6, 6 + 4, 6 + 4 + 2};
    CHECK(out[32 + i] == want[i % 4]);
    CHECK(out[48 + i] == 8);
  }
}

TEST_CASE("sim executor: a barrier publishes every subgroup's shared writes to the others") {
  const auto out = Run(R"(shared uint s[64];
  void main() {
    uint i = gl_LocalInvocationIndex;
    s[i] = i * 3u;
    barrier();
    data[gl_WorkGroupID.x * 64u + i] = s[63u - i] + gl_WorkGroupID.x;
  })", 64, 2, 8, std::vector<std::uint32_t>(128, 0));
  for (std::uint32_t g = 0; g < 2; ++g)
    for (std::uint32_t i = 0; i < 64; ++i) CHECK(out[g * 64 + i] == (63 - i) * 3 + g);
}

TEST_CASE("sim executor: a kernel's faults are reported, naming the kernel and its line") {
  CHECK_THROWS_WITH_AS(Run("void main() { data[gl_LocalInvocationIndex + 4u] = 1u; }", 8, 1, 8, std::vector<std::uint32_t>(8, 0)),
                       doctest::Contains("memcheck: an access of 4 bytes at byte 32 of a 32-byte binding 0"), sim::SimError);
  CHECK_THROWS_WITH_AS(Run("void main() { data[0] = 7u / data[1]; }", 1, 1, 8, std::vector<std::uint32_t>(2, 0)),
                       doctest::Contains("k k.comp:8: memcheck: integer division by zero"), sim::SimError);
  CHECK_THROWS_WITH_AS(Run("void main() { if (gl_LocalInvocationIndex < 4u) barrier(); data[0] = 1u; }", 8, 1, 8,
                           std::vector<std::uint32_t>(1, 0)),
                       doctest::Contains("synccheck: a barrier reached by 4 of the 8 running invocations of subgroup 0 (non-uniform control flow"), sim::SimError);
  CHECK_THROWS_WITH_AS(Run("void main() { uint k = 0u; while (data[0] == 0u) { k += 1u; } data[1] = k; }", 1, 1, 8,
                           std::vector<std::uint32_t>(2, 0)),
                       doctest::Contains("a hang"), sim::SimError);
}

TEST_CASE("sim executor: a kernel using what the simulator lacks is refused by name before it runs") {
  CHECK_THROWS_WITH_AS(Run("void main() { data[0] = floatBitsToUint(pow(uintBitsToFloat(data[1]), 2.5)); }", 1, 1, 8,
                           std::vector<std::uint32_t>(2, 0)),
                       doctest::Contains("k: uses GLSL.std.450 Pow, which the simulator does not execute"), rayspace::InputError);
}

TEST_CASE("sim executor: racecheck and initcheck on shared memory, lanes of one subgroup included") {
  const std::string race = R"(shared uint s[8];
  void main() {
    uint i = gl_LocalInvocationIndex;
    s[i] = i;
    BARRIER
    data[i] = s[(i + 1u) % 8u];
  })";
  auto with = [&race](const std::string& barrier) {
    std::string k = race;
    k.replace(k.find("BARRIER"), 7, barrier);
    return k;
  };
  // One subgroup of eight: lockstep runs every store before any load, yet nothing orders them.
  CHECK_THROWS_WITH_AS(Run(with(""), 8, 1, 8, std::vector<std::uint32_t>(8, 0)),
                       doctest::Contains("racecheck: invocation 0 reads shared word 1, which invocation 1 wrote with no barrier between "
                                         "(shared 's' word 1, workgroup (0, 0))"),
                       sim::SimError);
  const auto out = Run(with("barrier();"), 8, 1, 8, std::vector<std::uint32_t>(8, 0));
  for (std::uint32_t i = 0; i < 8; ++i) CHECK(out[i] == (i + 1) % 8);
  // A store after another invocation's load of the word, in the same interval.
  CHECK_THROWS_WITH_AS(Run(R"(shared uint s[8];
  void main() { uint i = gl_LocalInvocationIndex; s[i] = 1u; barrier(); data[i] = s[0]; s[0] = 2u; })", 8, 1, 8,
                           std::vector<std::uint32_t>(8, 0)),
                       doctest::Contains("racecheck: invocation 0 writes shared word 0, which other invocations read"), sim::SimError);
  CHECK_THROWS_WITH_AS(Run(R"(shared uint s[8];
  void main() { uint i = gl_LocalInvocationIndex; if (i != 3u) s[i] = i; barrier(); data[i] = s[i]; })", 8, 1, 8,
                           std::vector<std::uint32_t>(8, 0)),
                       doctest::Contains("initcheck: invocation 3 reads shared word 3, which no invocation of its workgroup wrote"),
                       sim::SimError);
  // Atomics race with nothing.
  const auto sum = Run(R"(shared uint s[1];
  void main() { if (gl_LocalInvocationIndex == 0u) s[0] = 0u; barrier(); atomicAdd(s[0], 1u); barrier();
                data[gl_LocalInvocationIndex] = s[0]; })", 16, 1, 8, std::vector<std::uint32_t>(16, 0));
  for (std::uint32_t i = 0; i < 16; ++i) CHECK(sum[i] == 16);
}

TEST_CASE("sim executor: the schedule orders workgroups and subgroups, reproducibly from its seed") {
  // Each workgroup's first invocation, and each subgroup's first lane, takes a ticket in the order it runs.
  const std::string tickets = R"(void main() {
    if (gl_LocalInvocationIndex == 0u) data[gl_WorkGroupID.x] = atomicAdd(data[40], 1u);
    if (gl_SubgroupInvocationID == 0u) data[20u + gl_WorkGroupID.x * 4u + gl_SubgroupID] = atomicAdd(data[41], 1u);
  })";
  using rayspace::wg::Order;
  const auto run = [&](Order o, std::uint64_t seed) { return Run(tickets, 32, 5, 8, std::vector<std::uint32_t>(42, 0), {o, seed}); };
  const auto fwd = run(Order::kForward, 0), rev = run(Order::kReverse, 0), rnd = run(Order::kRandom, 7), again = run(Order::kRandom, 7);
  for (std::uint32_t g = 0; g < 5; ++g) {
    CHECK(fwd[g] == g);
    CHECK(rev[g] == 4 - g);
    for (std::uint32_t s = 0; s < 4; ++s) {
      CHECK(fwd[20 + g * 4 + s] == g * 4 + s);
      CHECK(rev[20 + g * 4 + s] == (4 - g) * 4 + (3 - s));
    }
  }
  CHECK(rnd == again);
  CHECK(rnd != fwd);
  CHECK(rnd != rev);
  std::vector<std::uint32_t> groups(rnd.begin(), rnd.begin() + 5);
  std::sort(groups.begin(), groups.end());
  CHECK(groups == std::vector<std::uint32_t>{0, 1, 2, 3, 4});
}

namespace {
// The checker of the SimError `f` throws, or nothing when it throws none.
std::optional<sim::Checker> CheckerOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const sim::SimError& e) {
    REQUIRE_MESSAGE(e.checker().has_value(), e.what());
    return e.checker();
  }
  return std::nullopt;
}
// All checkers but `c`.
sim::Checks Without(sim::Checker c) { return {static_cast<std::uint8_t>(0xfu & ~(1u << static_cast<int>(c)))}; }
}  // namespace

TEST_CASE("sim executor: a shuffle from an inactive lane gives 0 whatever ran before it in that lane's place") {
  // Workgroup 0's even lanes compute v, workgroup 1's odd lanes; each active lane reads its
  // neighbour's v, which is inactive and never computed it in this workgroup (undefined: 0 here,
  // not the v its place held in the other workgroup, so that the schedule does not show).
  const std::string body = R"(void main() {
    const uint lane = gl_SubgroupInvocationID, i = gl_LocalInvocationIndex + 8u * gl_WorkGroupID.x;
    if ((lane + gl_WorkGroupID.x) % 2u == 0u) {
      const uint v = i + 1000u;
      data[i] = subgroupShuffle(v, lane ^ 1u) + 1u;
    }
  })";
  using rayspace::wg::Order;
  for (const Order o : {Order::kForward, Order::kReverse}) {
    const auto out = Run(body, 8, 2, 8, std::vector<std::uint32_t>(16, 0), {o, 0}, sim::Checks::None());
    for (std::uint32_t i = 0; i < 16; ++i) CHECK_MESSAGE(out[i] == ((i % 8 + i / 8) % 2 == 0 ? 1u : 0u), "element ", i);
  }
}

TEST_CASE("sim executor: racecheck on storage buffers, within a workgroup and between workgroups") {
  // barrier() orders shared memory only: another invocation's storage store is not yet ordered.
  const std::string neighbour = R"(void main() {
    uint i = gl_GlobalInvocationID.x;
    data[i] = i + 1u;
    FENCE barrier();
    data[64u + i] = data[gl_WorkGroupID.x * 8u + (i + 1u) % 8u];
  })";
  auto with = [&neighbour](const std::string& fence) {
    std::string k = neighbour;
    k.replace(k.find("FENCE"), 5, fence);
    return k;
  };
  CHECK_THROWS_WITH_AS(Run(with(""), 8, 2, 8, std::vector<std::uint32_t>(128, 0)),
                       doctest::Contains("racecheck: invocation 0 of workgroup 0 reads binding 0 word 1, which invocation 1 wrote with no "
                                         "barrier between"),
                       sim::SimError);
  const auto out = Run(with("memoryBarrierBuffer();"), 8, 2, 8, std::vector<std::uint32_t>(128, 0));
  for (std::uint32_t i = 0; i < 16; ++i) CHECK(out[64 + i] == (i - i % 8) + (i + 1) % 8 + 1);
  // Two workgroups of one dispatch are never ordered: a word one writes and the other reads.
  CHECK_THROWS_WITH_AS(Run(R"(void main() { if (gl_WorkGroupID.x == 0u) data[0] = 5u; else data[1] = data[0]; })", 1, 2, 8,
                           std::vector<std::uint32_t>(2, 0)),
                       doctest::Contains("racecheck: invocation 0 of workgroup 1 reads binding 0 word 0, which invocation 0 of workgroup 0 "
                                         "wrote"),
                       sim::SimError);
  CHECK_THROWS_WITH_AS(Run(R"(void main() { if (gl_WorkGroupID.x == 0u) data[1] = data[0]; else data[0] = 5u; })", 1, 2, 8,
                           std::vector<std::uint32_t>(2, 0)),
                       doctest::Contains("racecheck: invocation 0 of workgroup 1 writes binding 0 word 0, which invocations of other "
                                         "workgroups read"),
                       sim::SimError);
  // Reads by everyone of a word nobody writes, and atomics, race with nothing.
  const auto sum = Run(R"(void main() { atomicAdd(data[1], data[0]); })", 8, 4, 8, std::vector<std::uint32_t>{3, 0});
  CHECK(sum[1] == 3 * 32);
}

TEST_CASE("sim executor: each finding names its checker, and with that checker off the kernel runs on as a lenient device") {
  using C = sim::Checker;
  const std::vector<std::uint32_t> eight(8, 0);
  struct Planted {
    C checker;
    std::string body;
    std::uint32_t local, groups;
  };
  const std::vector<Planted> planted = {
      {C::kMemcheck, "void main() { data[gl_LocalInvocationIndex + 4u] = 1u; }", 8, 1},
      {C::kMemcheck, "void main() { data[0] = 7u / data[1]; }", 1, 1},
      {C::kMemcheck, "void main() { data[0] = 1u << (data[1] + 40u); }", 1, 1},
      {C::kSynccheck, "void main() { if (gl_LocalInvocationIndex < 4u) barrier(); data[gl_LocalInvocationIndex] = 1u; }", 8, 1},
      {C::kSynccheck, "void main() { if (gl_SubgroupID == 0u) return; barrier(); data[gl_LocalInvocationIndex] = 1u; }", 8, 1},
      {C::kRacecheck, "shared uint s[8]; void main() { s[gl_LocalInvocationIndex] = 1u; data[gl_LocalInvocationIndex] = s[0]; }", 8, 1},
      {C::kRacecheck, "void main() { data[0] = gl_WorkGroupID.x; }", 1, 2},
      {C::kInitcheck, "shared uint s[8]; void main() { data[gl_LocalInvocationIndex] = s[gl_LocalInvocationIndex]; }", 8, 1},
      {C::kInitcheck, "void main() { uint k; if (gl_LocalInvocationIndex > 3u) k = 1u; data[gl_LocalInvocationIndex] = k; }", 8, 1},
  };
  for (const Planted& p : planted) {
    CAPTURE(p.body);
    const auto run = [&](sim::Checks checks) { Run(p.body, p.local, p.groups, 4, eight, {}, checks); };
    CHECK(CheckerOf([&] { run({}); }) == p.checker);
    CHECK(CheckerOf([&] { run(Without(p.checker)); }) == std::nullopt);
    CHECK(CheckerOf([&] { run(sim::Checks::None()); }) == std::nullopt);
  }
  // A lenient device's values: an access outside the binding reads zero and writes nowhere.
  const auto out = Run("void main() { data[1] = data[9]; data[12] = 5u; }", 1, 1, 8, std::vector<std::uint32_t>{7, 7}, {},
                       Without(C::kMemcheck));
  CHECK(out == std::vector<std::uint32_t>{7, 0});
}

TEST_CASE("sim executor: initcheck follows undefined Function values to a branch, an index, an atomic or a store") {
  const std::vector<std::uint32_t> sixteen(16, 0);
  CHECK_THROWS_WITH_AS(Run("void main() { uint k; if (gl_LocalInvocationIndex > 3u) k = 1u; data[gl_LocalInvocationIndex] = k + 2u; }", 8, 1, 8,
                           sixteen),
                       doctest::Contains("initcheck: invocation 0 of workgroup (0, 0) stores to memory other invocations see an undefined value"),
                       sim::SimError);
  CHECK_THROWS_WITH_AS(Run("void main() { uint k; if (gl_LocalInvocationIndex == 0u) k = 1u; if (k * 2u > 1u) data[0] = 1u; }", 2, 1, 8,
                           sixteen),
                       doctest::Contains("initcheck: invocation 1 of workgroup (0, 0) branches on an undefined value"), sim::SimError);
  CHECK_THROWS_WITH_AS(Run("void main() { uint k[4]; k[0] = 1u; data[k[gl_LocalInvocationIndex % 2u]] = 1u; }", 2, 1, 8, sixteen),
                       doctest::Contains("initcheck: invocation 1 of workgroup (0, 0) indexes memory with an undefined value"), sim::SimError);
  CHECK_THROWS_WITH_AS(Run("void main() { uint k; atomicAdd(data[0], k); }", 1, 1, 8, sixteen),
                       doctest::Contains("gives an atomic operation an undefined value"), sim::SimError);
  // Defined on every path that uses it: the parts of an array written, a value chosen over an
  // undefined one, a variable written in a loop before it is read, a subgroup sum of defined values.
  const auto out = Run(R"(void main() {
    uint i = gl_LocalInvocationIndex;
    uint k[4];
    k[1] = i;
    uint u;
    uint v = i < 100u ? 7u : u;
    uint w;
    for (uint n = 0u; n < 3u; ++n) w = n;
    uint m;
    if (gl_SubgroupInvocationID < 2u) m = i * 100u;
    data[i] = k[1] + v + w + subgroupAdd(k[1]) + subgroupShuffle(m, 1u);
  })", 8, 1, 8, sixteen);
  for (std::uint32_t i = 0; i < 8; ++i) CHECK(out[i] == i + 7 + 2 + 28 + 100);
  // A shuffle from a lane whose value is undefined.
  CHECK_THROWS_WITH_AS(Run("void main() { uint m; if (gl_SubgroupInvocationID < 2u) m = 1u; data[gl_LocalInvocationIndex] = "
                           "subgroupShuffle(m, 2u); }",
                           8, 1, 8, sixteen),
                       doctest::Contains("stores to memory other invocations see an undefined value"), sim::SimError);
}

TEST_CASE("sim executor: the worst-conformant device fuses what a kernel leaves contractible and rounds loosely; lavapipe's does neither") {
  // data[0..2]: x, y, z as floats. x*y + z without `precise` may be fused; with it (a kernel of its
  // own: glslang marks every instance of an expression `precise` once one is), never.
  const std::string loose_body = R"(void main() {
    float x = uintBitsToFloat(data[0]), y = uintBitsToFloat(data[1]), z = uintBitsToFloat(data[2]);
    data[3] = floatBitsToUint(x * y + z);
    data[4] = floatBitsToUint(x / y);
    data[5] = floatBitsToUint(sqrt(y));
  })";
  const std::string precise_body = R"(void main() {
    float x = uintBitsToFloat(data[0]), y = uintBitsToFloat(data[1]), z = uintBitsToFloat(data[2]);
    precise float p = x * y + z;
    data[3] = floatBitsToUint(p);
  })";
  const float x = 1.0f + 0x1p-12f, y = 3.0f;
  const auto bits = [](float f) { return std::bit_cast<std::uint32_t>(f); };
  std::vector<std::uint32_t> in = {bits(x), bits(x), bits(-1.0f), 0, 0, 0};
  const sim::DeviceModelChoice worst{sim::DeviceModel::kWorst, 1};
  CHECK(Run(loose_body, 1, 1, 1, in)[3] == bits(0x1p-11f));  // lavapipe: rounded after the multiply
  CHECK(Run(loose_body, 1, 1, 1, in, {}, {}, worst)[3] == bits(0x1p-11f + 0x1p-24f));  // fused: one rounding
  CHECK(Run(precise_body, 1, 1, 1, in, {}, {}, worst)[3] == bits(0x1p-11f));         // precise: never fused
  in[1] = bits(y);
  const auto exact = Run(loose_body, 1, 1, 1, in), loose = Run(loose_body, 1, 1, 1, in, {}, {}, worst);
  CHECK(exact[4] == bits(x / y));
  CHECK(exact[5] == bits(std::sqrt(y)));
  CHECK(loose[4] != exact[4]);
  CHECK(loose[5] != exact[5]);
  CHECK(std::fabs(std::bit_cast<float>(loose[4]) - x / y) <= 3 * std::ldexp(1.0f, std::ilogb(x / y) - 23));
}

TEST_CASE("sim executor: a boolean specialization constant given as a number takes it as Vulkan reads a VkBool32") {
  // spirv-opt keeps a boolean's default when handed "1": the simulator must say "true" for it.
  const std::string body = R"(layout(constant_id = 2) const bool kFlag = false;
  void main() { data[0] = kFlag ? 7u : 3u; })";
  for (const auto& [value, expected] : {std::pair{"1", 7u}, std::pair{"0", 3u}}) {
    const sim::Program p = sim::Prepare(Compile(body, "k"), {{1, "1"}, {2, value}}, "k");
    std::vector<std::uint32_t> data(1, 0);
    sim::Dispatch d;
    d.bindings.push_back({reinterpret_cast<std::uint8_t*>(data.data()), data.size() * 4});
    sim::ExecStats stats;
    sim::Run(p, d, stats);
    CHECK_MESSAGE(data[0] == expected, "kFlag given as " << value);
  }
}

TEST_CASE("sim executor: subgroup layouts: linear is lavapipe's, shuffled deals invocations to places, partial leaves lanes inactive") {
  // Each invocation writes its subgroup, lane, the active lanes of its subgroup and the subgroup count
  // at its local index.
  const std::string body = R"(void main() {
    uint i = gl_LocalInvocationIndex;
    data[i] = gl_SubgroupID * 1000u + gl_SubgroupInvocationID;
    data[64 + i] = subgroupBallotBitCount(subgroupBallot(true));
    data[128 + i] = gl_NumSubgroups;
  })";
  const auto places = [](const std::vector<std::uint32_t>& out) {
    std::vector<std::uint32_t> p(out.begin(), out.begin() + 64);
    std::sort(p.begin(), p.end());
    return p;
  };
  const auto linear = Run(body, 64, 1, 8, std::vector<std::uint32_t>(192, 0));
  for (std::uint32_t i = 0; i < 64; ++i) {
    CHECK(linear[i] == i / 8 * 1000 + i % 8);
    CHECK(linear[64 + i] == 8);
    CHECK(linear[128 + i] == 8);
  }
  const sim::SubgroupLayoutChoice shuffled{sim::SubgroupLayout::kShuffled, 5, ""};
  const auto s = Run(body, 64, 1, 8, std::vector<std::uint32_t>(192, 0), {}, {}, {}, shuffled);
  CHECK(places(s) == places(linear));  // the same places, every one taken once
  CHECK(s != linear);                  // dealt in another order
  CHECK(Run(body, 64, 1, 8, std::vector<std::uint32_t>(192, 0), {}, {}, {}, shuffled) == s);  // reproducible from the seed
  const sim::SubgroupLayoutChoice partial{sim::SubgroupLayout::kPartial, 5, ""};
  const auto q = Run(body, 64, 1, 8, std::vector<std::uint32_t>(192, 0), {}, {}, {}, partial);
  std::set<std::uint32_t> taken(q.begin(), q.begin() + 64);
  CHECK(taken.size() == 64);  // no two invocations share a place
  bool narrow = false;
  for (std::uint32_t i = 0; i < 64; ++i) {
    CHECK(q[64 + i] >= 4);  // at least half the lanes of a subgroup of 8
    CHECK(q[64 + i] <= 8);
    narrow = narrow || q[64 + i] < 8;
    CHECK(q[128 + i] > 8);  // more subgroups than a full layout's
    if (i > 0) CHECK(q[i] > q[i - 1]);  // local order kept across subgroups and lanes
  }
  CHECK(narrow);
  // @KERNEL: another kernel's name leaves this one linear.
  CHECK(Run(body, 64, 1, 8, std::vector<std::uint32_t>(192, 0), {}, {}, {}, {sim::SubgroupLayout::kPartial, 5, "other"}) == linear);
}
