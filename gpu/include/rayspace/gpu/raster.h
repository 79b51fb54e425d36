// The raster pass as a real Vulkan graphics pipeline with multiple render targets: diffuse,
// specular, position, normal (RGBA32F), primitive id (R32_UINT), and a D32 depth attachment written
// through gl_FragDepth; LESS depth test, no culling.
#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include "rayspace/emu/streams.h"
#include "rayspace/gpu/vulkan.h"
#include "rayspace/layout.h"
#include "rayspace/scene_buffers.h"

namespace rayspace::gpu_backend {

// The colour attachments in location order (raster.frag): diffuse, specular, position, normal,
// primitive id; and the depth attachment. The device requirements (requirements.cpp) check these.
inline constexpr VkFormat kRasterColorFormats[] = {VK_FORMAT_R32G32B32A32_SFLOAT, VK_FORMAT_R32G32B32A32_SFLOAT,
                                                   VK_FORMAT_R32G32B32A32_SFLOAT, VK_FORMAT_R32G32B32A32_SFLOAT,
                                                   VK_FORMAT_R32_UINT};
inline constexpr VkFormat kRasterDepthFormat = VK_FORMAT_D32_SFLOAT;

// Spec violations planted for the validation tests (gpu/tests/validation_test.cpp); lavapipe runs
// the raster correctly either way.
struct RasterViolations {
  bool drop_subpass_dependencies = false;  // the copies read the attachments without a dependency
  bool differing_blend_states = false;     // one attachment's write mask differs (needs independentBlend)
};

// Draws the scene into `out`, the emulated raster's G-buffer layout (emu/streams.h).
vk::Status RasterGBuffer(vk::Context& ctx, std::span<const std::uint32_t> vert_spirv,
                         std::span<const std::uint32_t> frag_spirv, const layout::FrameConstants& fc, const SceneBuffers& scene,
                         std::uint32_t fault, emu::GBuffer& out, const RasterViolations& planted = {});

}  // namespace rayspace::gpu_backend
