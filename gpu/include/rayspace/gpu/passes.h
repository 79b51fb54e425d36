// The passes as Vulkan kernels: each call of emu/calls.h launched on the device, with the same inputs
// and outputs as its emulated counterpart.
#pragma once
#include <array>
#include <map>
#include <memory>
#include <span>
#include <string>
#include <type_traits>
#include <variant>
#include <vector>

#include "rayspace/emu/calls.h"
#include "rayspace/gpu/vulkan.h"
#include "rayspace/pass_registry.h"

namespace rayspace::gpu_backend {

// Planted faults: pass name -> fault number (1 = the pass's first fault), compiled into the kernel
// through a specialization constant.
using Faults = std::map<std::string, std::uint32_t>;

// A user's SPIR-V for a pass, by pass name, run in place of the built-in kernel (`--kernel`).
using KernelOverrides = std::map<std::string, std::vector<std::uint32_t>>;

// The SPIR-V of a built-in compute kernel by file name (gpu/shaders/<kernel>.comp), or empty.
std::span<const std::uint32_t> BuiltinKernel(std::string_view kernel);
// The file names of every built-in compute kernel (gpu/shaders/*.comp), sorted.
std::vector<std::string_view> BuiltinKernelNames();

// What a Vulkan pass produces for a call: its result, or nothing for a call that updates in place.
template <typename C>
using VulkanOut = std::conditional_t<std::is_void_v<typename C::Result>, std::monostate, typename C::Result>;

class VulkanPasses {
 public:
  // local_size: invocations per workgroup for every compute kernel (results must not depend on it).
  // One compute kernel per registered pass (rayspace/pass_registry.h), its pipeline made at its first
  // dispatch.
  // device vk::Context::kSimulatedDevice: the simulated GPU configured by `simulated`.
  static vk::Status Create(int device, const Faults& faults, std::unique_ptr<VulkanPasses>& out,
                           std::uint32_t local_size = 64, const KernelOverrides& overrides = {},
                           const sim::DeviceConfig& simulated = {});
  // One launch per call (emu/calls.h), same inputs and outputs as the emulated pass; in-place arrays
  // (Shade's accumulator, Intersect's hits or occlusion) are updated like the emulator does. Each is
  // defined in gpu/src/<kernel>.cpp beside its kernel's launch code.
#define RS_VULKAN_CALL(C) vk::Status Run(const emu::call::C& c, VulkanOut<emu::call::C>& out);
  RS_FRAME_CALLS(RS_VULKAN_CALL)
  RS_HIERARCHY_CALLS(RS_VULKAN_CALL)
#undef RS_VULKAN_CALL
  // Plants `faults` in place of the current ones (diff --inject-each: one device, a frame per fault):
  // each kernel whose fault changes makes its pipeline again at its next dispatch, the others keep
  // theirs. Only between frames.
  vk::Status SetFaults(const Faults& faults);
  // Starts extra_dispatches() and paged_arrays() anew (each fault's frame reports its own).
  void ResetCounts() { extra_dispatches_ = paged_arrays_ = 0; }
  const vk::Context& context() const { return *ctx_; }
  // Buffers that grow with the frame never exceed one binding: element-wise passes run over parts
  // of their streams, and arrays read at any index are paged (gpu/shaders/paged.glsl). This is the
  // most bytes one binding gets: maxStorageBufferRange, or less after LimitForTesting.
  std::size_t SplitBytes() const;
  // Test hook: behave like a device whose bindings hold at most `storage_bytes` and whose launches
  // have at most `groups_x` workgroups per row (0 keeps the device's limit).
  void LimitForTesting(std::size_t storage_bytes, std::uint32_t groups_x) { ctx_->LimitForTesting(storage_bytes, groups_x); }
  // Dispatches beyond one per pass call, from parts and splits (for reports and tests).
  std::size_t extra_dispatches() const { return extra_dispatches_; }
  // Arrays bound over more than one page so far (for reports and tests).
  std::size_t paged_arrays() const { return paged_arrays_; }
  // Launches of the pass's kernel so far, over the device's life (0 for the raster, a graphics pass).
  std::uint64_t launches(PassId id) const { return K(id).launches(); }
  // The lines of the pass's kernel the simulated device executed so far (nothing on a Vulkan device).
  std::optional<sim::LineCoverage> coverage(PassId id) const { return K(id).coverage(); }

 private:
  vk::Status ReduceInParts(std::span<const std::uint8_t> flags, std::span<const std::uint32_t> values, std::uint32_t s,
                           bool scan, std::vector<std::uint32_t>& out);
  vk::Status Build(std::uint32_t phase, std::span<const layout::Ray> rays, std::span<const std::uint32_t> order,
                   std::span<const layout::ConeNode> below, std::span<const std::uint32_t> first,
                   std::vector<layout::ConeNode>& nodes, std::uint32_t child_merge = layout::kChildMergeSequential);
  // Elements per part when each element takes `bytes_per_element` in the largest per-part binding.
  std::size_t PerPart(std::size_t bytes_per_element) const;
  // The same for the hierarchy's slot streams (traverse, reduce, traverse.compact), whose parts are
  // also kept to kStreamPartBytes a binding: on lavapipe a part's outputs are written by the kernel
  // and then read by the host, and parts of 128 MiB took 1.7 times as long per slot as parts of
  // 64 MiB or less (Sponza 512x512, docs/performance.md). Such parts count as split dispatches.
  static constexpr std::size_t kStreamPartBytes = std::size_t{64} << 20;
  std::size_t StreamPerPart(std::size_t bytes_per_element) const;
  vk::Status RaygenShadow(const emu::call::Raygen& c, emu::SparseRays& out);
  // The launch of an element-wise pass (gpu/src/elementwise.cpp).
  template <typename C>
  vk::Status Elementwise(const C& c, VulkanOut<C>& out);
  vk::Status RaygenSurface(const vk::Kernel& k, const emu::call::Raygen& c, emu::SparseRays& out);
  const vk::Kernel& K(PassId id) const { return kernels_[static_cast<std::size_t>(id)]; }
  std::unique_ptr<vk::Context> ctx_;
  std::uint32_t raster_fault_ = 0;
  std::size_t extra_dispatches_ = 0, paged_arrays_ = 0;
  std::array<vk::Kernel, kPassCount> kernels_;  // by PassId; the raster's stays empty (a graphics pipeline)
};

}  // namespace rayspace::gpu_backend
