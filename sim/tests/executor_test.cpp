// Known answers of the executor on small GLSL kernels compiled here with glslc: subgroup operations
// over active lanes, reconvergence after divergent branches and loops, barriers that publish shared
// memory across subgroups, and the faults a run reports (an access outside a binding, a division by
// zero, a barrier part of the workgroup never reaches, a hang).
#include <doctest/doctest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
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
                               std::vector<std::uint32_t> data, rayspace::wg::Schedule schedule = {}) {
  const sim::Program p = sim::Prepare(Compile(body, "k"), {{1, std::to_string(local)}}, "k");
  sim::Dispatch d;
  d.schedule = schedule;
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
                       doctest::Contains("k line 8: memcheck: integer division by zero"), sim::SimError);
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
