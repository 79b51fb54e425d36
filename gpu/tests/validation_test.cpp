// Under the Khronos validation layer with synchronization validation (Settings::validation), the raster
// is clean, and each planted violation of the kind lavapipe forgives makes the Vulkan call after it
// fail with the rule it breaks: a violation that comes back fails ctest, whose Vulkan tests all run
// validated (tests/CMakeLists.txt).
#include <doctest/doctest.h>

#include <memory>
#include <string>

#include "raster_frag.spv.h"
#include "raster_vert.spv.h"
#include "rayspace/gpu/raster.h"
#include "rayspace/gpu/validation.h"
#include "rayspace/scene.h"
#include "rayspace/scene_buffers.h"

namespace rayspace {
namespace {

struct Validated {
  ScopedSettings in_force{[](Settings& s) { s.validation = Validation::kSynchronization; }};
};

vk::Status Raster(vk::Context& ctx, const gpu_backend::RasterViolations& planted) {
  const Scene scene = LoadScene(std::string(RAYSPACE_SOURCE_DIR) + "/scenes/cornell-mirrors.json", {});
  const SceneBuffers buffers = FlattenScene(scene);
  emu::GBuffer g;
  return gpu_backend::RasterGBuffer(ctx, kSpirv_raster_vert, kSpirv_raster_frag, MakeFrameConstants(scene, buffers, 32, 24),
                                    buffers, 0, g, planted);
}

TEST_CASE("validation: the raster is clean, and a dropped subpass dependency and differing blend states are refused") {
  Validated on;
  std::unique_ptr<vk::Context> ctx;
  const vk::Status created = vk::Context::Create(-1, ctx);
  INFO("Vulkan: " << created.message);
  REQUIRE(created);
  const vk::Status clean = Raster(*ctx, {});
  INFO("clean raster: " << clean.message);
  CHECK(clean);
  const vk::Status dropped = Raster(*ctx, {.drop_subpass_dependencies = true});
  CHECK_FALSE(dropped);
  CHECK(dropped.message.find("SYNC-HAZARD-READ-AFTER-WRITE") != std::string::npos);
  const vk::Status blend = Raster(*ctx, {.differing_blend_states = true});
  CHECK_FALSE(blend);
  CHECK(blend.message.find("VUID-VkPipelineColorBlendStateCreateInfo-pAttachments-00605") != std::string::npos);
  CHECK(blend.call.empty());  // a validation failure carries no VkResult
  CHECK_FALSE(vk::ValidationPending());
}

}  // namespace
}  // namespace rayspace
