#include "backend_setup.h"

#include <algorithm>

#include "rayspace/error.h"
#include "rayspace/layout.h"
#ifdef RAYSPACE_HAVE_VULKAN
#include "rayspace/gpu/backend.h"
#endif

namespace rayspace::app {

#ifdef RAYSPACE_HAVE_VULKAN
namespace {
struct VulkanOwner {
  std::unique_ptr<gpu_backend::VulkanPasses> gpu;
  std::unique_ptr<emu::FramePasses> frame;
  std::unique_ptr<emu::HierarchyPasses> hierarchy;
};
}  // namespace
#endif

void CheckFrameFits(const Backend& backend, int width, int height, std::size_t lights) {
  if (backend.max_buffer_bytes == 0) return;
  // The largest per-pixel binding: surfaces (80 bytes), shadow-ray slots (64 bytes per light), colour
  // accumulator (3 x 8 bytes); reflection and refraction slots are one ray per pixel.
  const std::size_t per_pixel = std::max<std::size_t>({sizeof(gpu::Surface), sizeof(gpu::Ray) * std::max<std::size_t>(lights, 1), 24});
  const std::size_t pixels = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  if (pixels * per_pixel > backend.max_buffer_bytes)
    ThrowInput("--size {}x{}: per-pixel buffers of {} bytes exceed maxStorageBufferRange {} of '{}'; at most {} pixels fit",
               width, height, pixels * per_pixel, backend.max_buffer_bytes, backend.device, backend.max_buffer_bytes / per_pixel);
}

Backend MakeBackend(const std::string& name, int device, int local_size, const std::map<std::string, std::uint32_t>& faults,
                    std::size_t split_bytes) {
  Backend b;
  if (name == "emu") {
    b.device = "host";
    return b;
  }
  if (name != "vulkan") ThrowInput("--backend '{}': expected emu or vulkan", name);
#ifdef RAYSPACE_HAVE_VULKAN
  auto owner = std::make_shared<VulkanOwner>();
  if (vk::Status s = gpu_backend::VulkanPasses::Create(device, faults, owner->gpu, static_cast<std::uint32_t>(local_size)); !s) {
    if (s.message.rfind("--device", 0) == 0) ThrowInput("{}", s.message);  // a bad argument, not a failure
    throw std::runtime_error("Vulkan: " + s.message);
  }
  owner->gpu->SetSplitBytes(split_bytes);
  owner->frame = gpu_backend::MakeVulkanFramePasses(*owner->gpu);
  owner->hierarchy = gpu_backend::MakeVulkanHierarchyPasses(*owner->gpu);
  b.name = "vulkan";
  b.device = owner->gpu->context().device_name();
  b.max_buffer_bytes = static_cast<std::size_t>(owner->gpu->context().max_storage_buffer_range());
  b.frame = owner->frame.get();
  b.hierarchy = owner->hierarchy.get();
  b.owner = owner;
  b.extra_dispatches = [](const Backend& be) {
    return static_cast<const VulkanOwner*>(be.owner.get())->gpu->extra_dispatches();
  };
  return b;
#else
  (void)device;
  (void)local_size;
  (void)faults;
  (void)split_bytes;
  ThrowInput("--backend vulkan: this build of rayspace has no Vulkan backend (the Vulkan loader or glslc was missing)");
#endif
}

}  // namespace rayspace::app
