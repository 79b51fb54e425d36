// --strict-math's claim on the kernels themselves: specialised as a strict pipeline runs them
// (kStrictMath true, no fault), a kernel holds no division, square root or inverse square root a
// conformant device may round loosely; the kernels that still do are the ones --strict-math refuses
// by name (vk::Context::CreateKernel runs the same check).
#include <doctest/doctest.h>

#include <map>
#include <string>
#include <vector>

#include "rayspace/gpu/passes.h"
#include "rayspace/sim/module_tools.h"

namespace rayspace {
namespace {

std::vector<std::string> LooseInStrictPipeline(std::string_view kernel, bool strict) {
  const std::map<std::uint32_t, std::string> spec = {{0, "0"}, {1, "64"}, {2, strict ? "true" : "false"}};
  return sim::LooselyRounded(sim::Specialized(gpu_backend::BuiltinKernel(kernel), spec, std::string(kernel)));
}

TEST_CASE("strict math: a strict pipeline of every kernel divides and takes roots only through the exact functions") {
  std::map<std::string, std::vector<std::string>> loose;
  for (std::string_view k : gpu_backend::BuiltinKernelNames())
    if (auto found = LooseInStrictPipeline(k, true); !found.empty()) loose[std::string(k)] = found;
  for (const auto& [kernel, found] : loose) MESSAGE(kernel, ": ", found.size(), " left, first ", found.front());
  // The grids' build bins in double, which has no integer-exact division here: refused.
  CHECK(loose.size() == 1);
  CHECK(loose.count("grid_build") == 1);
}

// The check can fail: without kStrictMath the same kernels divide and take roots as the device does.
TEST_CASE("strict math: the check finds the device's division and root in a kernel built without --strict-math") {
  const std::vector<std::string> found = LooseInStrictPipeline("raygen_shadow", false);
  REQUIRE_FALSE(found.empty());
  bool div = false, root = false;
  for (const std::string& f : found) {
    div = div || f.find("OpFDiv (32-bit)") != std::string::npos;
    root = root || f.find("Sqrt (32-bit)") != std::string::npos;
    CHECK(f.find(".glsl:") + f.find(".comp:") != 2 * std::string::npos);  // a source line from the debug information
  }
  CHECK(div);
  CHECK(root);
  CHECK(sim::LooselyRounded(std::vector<std::uint32_t>{1, 2, 3}).empty());  // not SPIR-V
}

}  // namespace
}  // namespace rayspace
