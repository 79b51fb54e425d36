// The raster pass as a real Vulkan graphics pipeline: a primitive-id colour target (R32_UINT) and a
// D32 depth attachment written through gl_FragDepth, LESS depth test, no culling.
#pragma once
#include <cstdint>
#include <span>
#include <vector>

#include "rayspace/gpu/vulkan.h"
#include "rayspace/layout.h"

namespace rayspace::gpu_backend {

vk::Status RasterPrimitiveIds(vk::Context& ctx, std::span<const std::uint32_t> vert_spirv,
                              std::span<const std::uint32_t> frag_spirv, const gpu::FrameConstants& fc,
                              const std::vector<gpu::Triangle>& triangles, std::uint32_t fault,
                              std::vector<std::uint32_t>& prim, std::vector<float>& depth);

}  // namespace rayspace::gpu_backend
