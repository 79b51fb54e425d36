// The pass registry against the Vulkan backend: every registered compute pass has a built-in kernel,
// every kernel in gpu/shaders/ belongs to a registered pass, and each kernel's bindings and
// push-constant block, read back from its SPIR-V, are the registry's (so GLSL, contract header and
// registry cannot drift apart). The contract check must also refuse kernels that break it.
#include <doctest/doctest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>

#include "rayspace/gpu/kernel_check.h"
#include "rayspace/gpu/passes.h"
#include "rayspace/gpu/requirements.h"
#include "rayspace/pass_registry.h"

namespace rayspace {
namespace {

using gpu_backend::BuiltinKernel;
using gpu_backend::BuiltinKernelNames;
using gpu_backend::CheckKernel;
using gpu_backend::KernelInterface;
using gpu_backend::ReflectKernel;

TEST_CASE("registry: every compute pass has a built-in kernel and every kernel a pass") {
  std::set<std::string_view> used;
  for (const PassSpec& p : kPasses) {
    if (p.graphics) continue;
    INFO("pass ", std::string(p.name));
    CHECK_FALSE(BuiltinKernel(p.kernel).empty());
    used.insert(p.kernel);
  }
  for (std::string_view k : BuiltinKernelNames()) {
    INFO("kernel gpu/shaders/", std::string(k), ".comp");
    CHECK(used.count(k) == 1);
  }
  CHECK(used.size() == BuiltinKernelNames().size());
}

TEST_CASE("registry: each kernel's reflected bindings and push constants are the registry's") {
  for (const PassSpec& p : kPasses) {
    if (p.graphics) continue;
    INFO("pass ", std::string(p.name));
    KernelInterface k;
    REQUIRE(ReflectKernel(BuiltinKernel(p.kernel), k));
    CHECK(k.compute);
    CHECK(k.local_size_from_constant_1);
    CHECK(k.push_bytes == p.push_bytes);
    // Bindings 0 .. bindings-1, each once, all storage buffers in set 0.
    std::set<std::uint32_t> seen;
    for (const auto& b : k.bindings) {
      CHECK(b.storage_buffer);
      CHECK(b.set == 0);
      CHECK(seen.insert(b.binding).second);
    }
    CHECK(seen.size() == p.bindings);
    if (!seen.empty()) CHECK(*seen.rbegin() == p.bindings - 1);
    const vk::Status st = CheckKernel(p, BuiltinKernel(p.kernel));
    INFO(st.message);
    CHECK(st);
  }
}

TEST_CASE("registry: the contract check refuses a kernel that binds outside the pass or pushes another block") {
  // traverse.comp binds 15 buffers; reduce has 6 bindings.
  const vk::Status bindings = CheckKernel(Pass(PassId::kReduce), BuiltinKernel("traverse"));
  CHECK_FALSE(bindings);
  CHECK(bindings.message.find("pass 'reduce'") != std::string::npos);
  INFO(bindings.message);
  CHECK(bindings.message.find("binding 6") != std::string::npos);
  // trim.comp has 5 bindings like raygen's but a 12-byte push block against raygen.reflection's 8.
  const vk::Status push = CheckKernel(Pass(PassId::kRaygenReflection), BuiltinKernel("trim"));
  CHECK_FALSE(push);
  CHECK(push.message.find("push-constant") != std::string::npos);
  // The raster is a graphics pipeline.
  CHECK_FALSE(CheckKernel(Pass(PassId::kRaster), BuiltinKernel("reduce")));
  // Not SPIR-V at all.
  const std::uint32_t junk[8] = {1, 2, 3, 4, 5, 6, 7, 8};
  CHECK_FALSE(CheckKernel(Pass(PassId::kReduce), junk));
}

// A user kernel in GLSL: compiled like the built-in ones, then checked.
vk::Status CheckSource(PassId pass, const std::string& glsl) {
  const std::filesystem::path path = std::filesystem::temp_directory_path() / "rayspace-registry-test.comp";
  std::ofstream(path) << glsl;
  std::vector<std::uint32_t> spirv;
  vk::Status st = gpu_backend::LoadKernelFile(path.string(), spirv);
  std::filesystem::remove(path);
  return st ? CheckKernel(Pass(pass), spirv) : st;
}

const char* kHeader = "#version 460\n#include \"common.glsl\"\n";

TEST_CASE("registry: user kernels in GLSL are compiled and checked member by member") {
  // The contract's own block: accepted.
  CHECK(CheckSource(PassId::kResolve, std::string(kHeader) +
                                          "layout(std430, binding = kResolveBindAccum) readonly buffer A { uint64_t a[]; };\n"
                                          "layout(std430, binding = kResolveBindRgb) writeonly buffer B { uint b[]; };\n"
                                          "layout(push_constant) uniform Block { ElementwisePush pc; };\n"
                                          "void main() { if (GlobalIndex() < pc.count) b[GlobalIndex()] = uint(a[GlobalIndex()]); }\n"));
  // Same size, another layout: a float where ReducePush has a uint.
  const vk::Status wrong_layout = CheckSource(PassId::kReduce, std::string(kHeader) +
                                                             "layout(std430, binding = 0) readonly buffer F { uint f[]; };\n"
                                                             "layout(push_constant) uniform P { uint n; float phase; uint s, c, b; } pc;\n"
                                                             "void main() { if (pc.phase > 0.0) f[0]; }\n");
  CHECK_FALSE(wrong_layout);
  CHECK(wrong_layout.message.find("float at byte 4") != std::string::npos);
  // A fixed workgroup size the host does not know.
  const vk::Status local = CheckSource(PassId::kResolve, "#version 460\nlayout(local_size_x = 64) in;\nvoid main() {}\n");
  CHECK_FALSE(local);
  CHECK(local.message.find("local_size_x_id") != std::string::npos);
  // A uniform buffer where the contract binds storage buffers.
  const vk::Status ubo = CheckSource(PassId::kResolve, std::string(kHeader) +
                                                           "layout(std140, binding = 1) uniform U { uint u; };\n"
                                                           "void main() { if (u == 0u) return; }\n");
  CHECK_FALSE(ubo);
  CHECK(ubo.message.find("binding 1") != std::string::npos);
  // GLSL that does not compile: the error names the file.
  const vk::Status bad = CheckSource(PassId::kResolve, "#version 460\nvoid main() { undefined_thing(); }\n");
  CHECK_FALSE(bad);
  CHECK(bad.message.find("does not compile") != std::string::npos);
}

// The subgroup features each kernel needs are read from its SPIR-V's capabilities, which is what a
// device is checked against (rayspace devices, and kernel creation refusing by name).
TEST_CASE("registry: each kernel's subgroup features are its SPIR-V's capabilities") {
  constexpr VkSubgroupFeatureFlags kScan =
      VK_SUBGROUP_FEATURE_BASIC_BIT | VK_SUBGROUP_FEATURE_ARITHMETIC_BIT | VK_SUBGROUP_FEATURE_BALLOT_BIT;
  CHECK(vk::SubgroupFeaturesOf(BuiltinKernel("trim")) == kScan);  // elect, inclusive add, ballot
  CHECK(vk::SubgroupFeaturesOf(BuiltinKernel("traverse_compact")) == (kScan | VK_SUBGROUP_FEATURE_SHUFFLE_BIT | VK_SUBGROUP_FEATURE_VOTE_BIT));
  CHECK(vk::SubgroupFeaturesOf(BuiltinKernel("surfaces")) == 0);  // no subgroup operation
  std::set<std::string> vote;
  for (std::string_view k : BuiltinKernelNames())
    if (vk::SubgroupFeaturesOf(BuiltinKernel(k)) & VK_SUBGROUP_FEATURE_VOTE_BIT) vote.insert(std::string(k));
  CHECK(vote == std::set<std::string>{"traverse_compact"});  // subgroupAll in its level phase
  // Not SPIR-V, or cut short: no feature, no crash.
  CHECK(vk::SubgroupFeaturesOf(std::vector<std::uint32_t>{1, 2, 3, 4, 5, 6}) == 0);
  const auto trim = BuiltinKernel("trim");
  CHECK(vk::SubgroupFeaturesOf(trim.first(6)) == 0);
  CHECK(vk::SubgroupFeatureName(VK_SUBGROUP_FEATURE_VOTE_BIT) == "VK_SUBGROUP_FEATURE_VOTE_BIT");
}

}  // namespace
}  // namespace rayspace
