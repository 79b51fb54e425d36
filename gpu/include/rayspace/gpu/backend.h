// The Vulkan kernels as a backend of the frame and the hierarchy (emu/backend.h). The adapters
// borrow a VulkanPasses, which must outlive them; a failed Vulkan call throws emu::BackendError
// naming the pass and the call.
#pragma once
#include <memory>

#include "rayspace/emu/backend.h"
#include "rayspace/gpu/passes.h"

namespace rayspace::gpu_backend {

std::unique_ptr<emu::FramePasses> MakeVulkanFramePasses(VulkanPasses& gpu);
std::unique_ptr<emu::HierarchyPasses> MakeVulkanHierarchyPasses(VulkanPasses& gpu);

}  // namespace rayspace::gpu_backend
