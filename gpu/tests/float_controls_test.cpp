// The float controls a device offers are requested by adding them to each kernel's module: the
// result declares them for its entry point, stays valid SPIR-V, and asks nothing twice.
#include <doctest/doctest.h>

#include <vector>

#include "rayspace/gpu/float_controls.h"
#include "rayspace/gpu/passes.h"
#include "rayspace/sim/module_tools.h"

namespace rayspace {
namespace {

TEST_CASE("float controls: a kernel asked for both declares both and stays valid") {
  for (const char* kernel : {"trim", "intersect", "grid_build"}) {
    CAPTURE(kernel);
    const auto spirv = gpu_backend::BuiltinKernel(kernel);
    REQUIRE_FALSE(spirv.empty());
    const vk::FloatControls before = vk::DeclaredFloatControls(spirv);
    CHECK_FALSE(before.denorm_preserve);  // the kernels are compiled without them
    CHECK_FALSE(before.round_to_nearest);
    const std::vector<std::uint32_t> both = vk::WithFloatControls(spirv, {true, true});
    const vk::FloatControls after = vk::DeclaredFloatControls(both);
    CHECK(after.denorm_preserve);
    CHECK(after.round_to_nearest);
    CHECK(sim::ValidationError(both).empty());
    CHECK(both.size() == spirv.size() + 2 * 2 + 2 * 4);  // two capabilities, two modes for one entry point
    CHECK(vk::WithFloatControls(both, {true, true}) == both);  // nothing asked twice
    const std::vector<std::uint32_t> rte = vk::WithFloatControls(spirv, {false, true});
    CHECK_FALSE(vk::DeclaredFloatControls(rte).denorm_preserve);
    CHECK(vk::DeclaredFloatControls(rte).round_to_nearest);
    CHECK(sim::ValidationError(rte).empty());
  }
  const std::vector<std::uint32_t> none = vk::WithFloatControls(gpu_backend::BuiltinKernel("trim"), {});
  CHECK(none.size() == gpu_backend::BuiltinKernel("trim").size());
  CHECK(vk::WithFloatControls(std::vector<std::uint32_t>{1, 2, 3}, {true, true}) == std::vector<std::uint32_t>{1, 2, 3});
  CHECK(vk::FloatControls{true, false}.Describe() == "DenormPreserve");
  CHECK(vk::FloatControls{}.Describe() == "none");
}

}  // namespace
}  // namespace rayspace
