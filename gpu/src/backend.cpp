// The Vulkan passes behind the backend interface (emu/backend.h): each call launches its kernel and
// turns a failed Vulkan call into a BackendError naming the call.
#include "rayspace/gpu/backend.h"

#include <fmt/format.h>

#include "rayspace/error.h"

namespace rayspace::gpu_backend {
namespace {

template <typename C>
typename C::Result Launch(VulkanPasses& gpu, const C& c) {
  VulkanOut<C> out;
  if (const vk::Status s = gpu.Run(c, out); !s && s.refused)
    ThrowInput("{}, pass {}: {}", gpu.context().simulated() ? "simulated GPU" : "Vulkan backend", C::kName, s.message);
  else if (!s)
    throw emu::BackendError(fmt::format("{}, pass {}: {}", gpu.context().simulated() ? "simulated GPU" : "Vulkan backend", C::kName, s.message),
                            s.checker, s.finding, s.device_fault);
  if constexpr (!std::is_void_v<typename C::Result>) return out;
}

#define RS_LAUNCH_CALL(C) emu::call::C::Result C(const emu::call::C& c) override { return Launch(gpu_, c); }

class VulkanFrame final : public emu::FramePasses {
 public:
  explicit VulkanFrame(VulkanPasses& gpu) : gpu_(gpu) {}
  std::string Name() const override { return gpu_.context().simulated() ? "sim" : "vulkan"; }
  RS_FRAME_CALLS(RS_LAUNCH_CALL)

 private:
  VulkanPasses& gpu_;
};

class VulkanHierarchy final : public emu::HierarchyPasses {
 public:
  explicit VulkanHierarchy(VulkanPasses& gpu) : gpu_(gpu) {}
  std::string Name() const override { return gpu_.context().simulated() ? "sim" : "vulkan"; }
  RS_HIERARCHY_CALLS(RS_LAUNCH_CALL)

 private:
  VulkanPasses& gpu_;
};

}  // namespace

std::unique_ptr<emu::FramePasses> MakeVulkanFramePasses(VulkanPasses& gpu) { return std::make_unique<VulkanFrame>(gpu); }
std::unique_ptr<emu::HierarchyPasses> MakeVulkanHierarchyPasses(VulkanPasses& gpu) {
  return std::make_unique<VulkanHierarchy>(gpu);
}

}  // namespace rayspace::gpu_backend
