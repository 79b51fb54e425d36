// The module a Vulkan device is given (vk::Context::CreatePipeline): the kernel with its
// specialization constants frozen and the branches they decide removed. It must stay valid, drop the
// strict-math path when --strict-math is off (lavapipe would otherwise copy it into every Div and Sqrt
// call site before removing it), and change no computing instruction of what remains: the same
// float operations, in the same number, as the fully specialised module the simulator's strict check
// reads.
#include <doctest/doctest.h>

#include <map>
#include <string>
#include <vector>

#include <spirv/unified1/spirv.hpp11>

#include "rayspace/gpu/passes.h"
#include "rayspace/sim/module_tools.h"

namespace rayspace {
namespace {

std::map<std::uint32_t, std::string> Spec(bool strict) { return {{0, "0"}, {1, "64"}, {2, strict ? "true" : "false"}}; }

// How many instructions of `op` the module holds; for OpUDiv only those on 64-bit integers (the
// strict path's quotient), recognised by their result type.
std::size_t Count(const std::vector<std::uint32_t>& m, spv::Op op) {
  std::map<std::uint32_t, std::uint32_t> int_width;
  std::size_t n = 0;
  for (std::size_t at = 5; at < m.size() && (m[at] >> 16) != 0; at += m[at] >> 16) {
    const auto o = static_cast<spv::Op>(m[at] & 0xffffu);
    if (o == spv::Op::OpTypeInt) int_width[m[at + 1]] = m[at + 2];
    if (o != op) continue;
    if (op == spv::Op::OpUDiv && int_width[m[at + 1]] != 64) continue;
    ++n;
  }
  return n;
}

TEST_CASE("device module: every built-in kernel stays valid SPIR-V with its branches decided") {
  for (std::string_view k : gpu_backend::BuiltinKernelNames())
    for (const bool strict : {false, true}) {
      const auto decided = sim::WithBranchesDecided(gpu_backend::BuiltinKernel(k), Spec(strict), std::string(k));
      CHECK_MESSAGE(sim::ValidationError(decided).empty(), k, strict ? " strict: " : ": ", sim::ValidationError(decided));
    }
}

TEST_CASE("device module: the strict path is gone without --strict-math and kept with it") {
  const auto build = gpu_backend::BuiltinKernel("build");
  REQUIRE(Count({build.begin(), build.end()}, spv::Op::OpUDiv) > 0);  // the module as compiled has both paths
  CHECK(Count(sim::WithBranchesDecided(build, Spec(false), "build"), spv::Op::OpUDiv) == 0);
  CHECK(Count(sim::WithBranchesDecided(build, Spec(true), "build"), spv::Op::OpUDiv) > 0);
  // Without strict math the device's division remains; with it, none (the strict path divides in integers).
  CHECK(Count(sim::WithBranchesDecided(build, Spec(false), "build"), spv::Op::OpFDiv) > 0);
}

// Deciding branches must not touch arithmetic: every float operation of the kernel's live code is
// still there. The simulator's full specialisation (inlined, dead code removed) is the reference for
// which operations are live; inlining copies a function's body per call, so the decided module,
// whose functions are still called, holds at most as many and at least one of each kind.
TEST_CASE("device module: no float operation of the live code is removed or added") {
  for (std::string_view k : gpu_backend::BuiltinKernelNames()) {
    const auto spirv = gpu_backend::BuiltinKernel(k);
    const auto decided = sim::WithBranchesDecided(spirv, Spec(false), std::string(k));
    const auto inlined = sim::Specialized(spirv, Spec(false), std::string(k));
    const std::vector<std::uint32_t> original(spirv.begin(), spirv.end());
    for (const spv::Op op : {spv::Op::OpFAdd, spv::Op::OpFSub, spv::Op::OpFMul, spv::Op::OpFDiv, spv::Op::OpExtInst}) {
      const std::size_t d = Count(decided, op), in = Count(inlined, op), orig = Count(original, op);
      CHECK_MESSAGE(d <= orig, k, " op ", static_cast<int>(op), ": ", d, " decided, ", orig, " compiled");
      CHECK_MESSAGE((in == 0) == (d == 0), k, " op ", static_cast<int>(op), ": ", d, " decided, ", in, " live");
    }
  }
}

TEST_CASE("device module: a module SPIRV-Tools rejects is an error naming it") {
  const std::vector<std::uint32_t> junk = {spv::MagicNumber, 0x00010500, 0, 10, 0, 0xdeadbeef};
  CHECK_THROWS_WITH(sim::WithBranchesDecided(junk, Spec(false), "kernel mine.spv"),
                    doctest::Contains("kernel mine.spv: spirv-opt could not freeze its specialization constants"));
}

}  // namespace
}  // namespace rayspace
