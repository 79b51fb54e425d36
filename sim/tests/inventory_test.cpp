// The simulator's scope against the built-in kernels (stage 0 of docs/simulator.md): every kernel is
// valid SPIR-V, uses only what the scope lists, and carries debug information that changes none of
// its computing instructions.
#include <doctest/doctest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <spirv-tools/libspirv.hpp>

#include "kernel_table.h"
#include "rayspace/sim/grammar.h"
#include "rayspace/sim/inventory.h"
#include "rayspace/sim/module_tools.h"
#include "rayspace/sim/scope.h"

namespace {

using rayspace::gpu_backend::kBuiltinKernels;
namespace sim = rayspace::sim;

std::string Listed(const std::vector<sim::Feature>& fs) {
  std::string s;
  for (const sim::Feature& f : fs) s += (s.empty() ? "" : ", ") + f.kind + " " + f.name;
  return s;
}

}  // namespace

TEST_CASE("sim: every built-in kernel is valid SPIR-V for Vulkan 1.2 (spirv-val)") {
  CHECK(std::size(kBuiltinKernels) >= 20);
  for (const auto& k : kBuiltinKernels) CHECK_MESSAGE(sim::ValidationError(k.spirv).empty(), k.name, ": ", sim::ValidationError(k.spirv));
}

TEST_CASE("sim: the built-in kernels use only what the simulator's scope lists") {
  for (const auto& k : kBuiltinKernels) {
    const std::vector<sim::Feature> outside = sim::OutsideScope(sim::InventoryOf(k.spirv, std::string(k.name)));
    CHECK_MESSAGE(outside.empty(), k.name, " uses what the simulator lacks: ", Listed(outside));
  }
}

TEST_CASE("sim: every name in the scope is one the SPIR-V grammar lists") {
  for (const sim::ScopeEntry& e : sim::kScope) CHECK_MESSAGE(sim::GrammarLists(e.kind, e.name), e.kind, " ", e.name);
  CHECK_FALSE(sim::GrammarLists("Opcode", "OpIAddd"));
  CHECK(sim::NameOf("Opcode", 128) == "OpIAdd");
  CHECK(sim::NameOf("StorageClass", 12) == "StorageBuffer");
  CHECK(sim::NameOf("GLSL.std.450", 37) == "FMin");
}

TEST_CASE("sim: a module using what the scope lacks is named feature by feature") {
  const char* text = R"(
               OpCapability Shader
               OpCapability Int8
               OpMemoryModel Logical GLSL450
               OpEntryPoint GLCompute %main "main"
               OpExecutionMode %main LocalSize 1 1 1
       %void = OpTypeVoid
         %fn = OpTypeFunction %void
      %float = OpTypeFloat 32
      %uchar = OpTypeInt 8 0
        %one = OpConstant %float 1
       %main = OpFunction %void None %fn
      %entry = OpLabel
          %q = OpQuantizeToF16 %float %one
               OpReturn
               OpFunctionEnd
)";
  spvtools::SpirvTools tools(SPV_ENV_VULKAN_1_2);
  std::vector<std::uint32_t> words;
  REQUIRE(tools.Assemble(text, &words));
  const std::vector<sim::Feature> outside = sim::OutsideScope(sim::InventoryOf(words, "planted"));
  CHECK(Listed(outside) == "Capability Int8, Opcode OpQuantizeToF16");
  CHECK_THROWS_WITH(sim::InventoryOf(std::vector<std::uint32_t>{1, 2, 3}, "garbage.spv"),
                    doctest::Contains("garbage.spv: not a SPIR-V module"));
}

TEST_CASE("sim: glslc -g leaves the computing instructions of every kernel unchanged") {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("rayspace-sim-test-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  for (const auto& k : kBuiltinKernels) {
    const sim::Inventory used = sim::InventoryOf(k.spirv, std::string(k.name));
    CHECK_MESSAGE(used.at("Opcode").count("OpLine"), k.name, " carries no OpLine: not compiled with -g");
    const fs::path src = fs::path(RAYSPACE_SOURCE_DIR) / "gpu" / "shaders" / (std::string(k.name) + ".comp");
    const fs::path out = dir / (std::string(k.name) + ".spv");
    const std::string cmd = std::string(RAYSPACE_TEST_GLSLC) + " -O0 --target-env=vulkan1.2 -I " + RAYSPACE_SOURCE_DIR +
                            "/core/contract/include -I " + RAYSPACE_SOURCE_DIR + "/gpu/shaders " + src.string() + " -o " + out.string();
    REQUIRE_MESSAGE(std::system(cmd.c_str()) == 0, cmd);
    std::ifstream in(out, std::ios::binary);
    std::vector<std::uint32_t> plain(fs::file_size(out) / 4);
    in.read(reinterpret_cast<char*>(plain.data()), static_cast<std::streamsize>(plain.size() * 4));
    CHECK_MESSAGE(sim::WithoutDebugInfo(k.spirv, std::string(k.name)) == sim::WithoutDebugInfo(plain, "plain"), k.name,
                  ": the debug build computes differently from the plain one");
  }
  fs::remove_all(dir);
}
