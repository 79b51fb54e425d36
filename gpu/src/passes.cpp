// The Vulkan passes' shared part: a kernel for every registered pass and the split size.
#include "kernel_table.h"
#include "rayspace/gpu/passes.h"
#include "kernel_util.h"

namespace rayspace::gpu_backend {
using namespace detail;

std::span<const std::uint32_t> BuiltinKernel(std::string_view kernel) {
  for (const BuiltinSpirv& k : kBuiltinKernels)
    if (k.name == kernel) return k.spirv;
  return {};
}

std::vector<std::string_view> BuiltinKernelNames() {
  std::vector<std::string_view> names;
  for (const BuiltinSpirv& k : kBuiltinKernels) names.push_back(k.name);
  return names;
}

namespace {
// The fault `faults` plants in `pass`, or 0 (none).
std::uint32_t FaultOf(const Faults& faults, std::string_view pass) {
  auto it = faults.find(std::string(pass));
  return it == faults.end() ? 0u : it->second;
}
}  // namespace

// One kernel per registered compute pass, named by the pass (a planted fault stays in its pass even
// where passes share a kernel file, as compress, sort and decompress do).
vk::Status VulkanPasses::Create(int device, const Faults& faults, std::unique_ptr<VulkanPasses>& out,
                                std::uint32_t local_size, const KernelOverrides& overrides, const sim::DeviceConfig& simulated) {
  auto p = std::make_unique<VulkanPasses>();
  RS_TRY(vk::Context::Create(device, p->ctx_, simulated));
  for (const PassSpec& spec : kPasses) {
    if (spec.graphics) continue;
    // Without 64-bit floats the grid build's pipelines are not made; its calls fail naming the feature.
    if (spec.kernel == "grid_build" && !p->ctx_->float64()) continue;
    std::span<const std::uint32_t> spirv = BuiltinKernel(spec.kernel);
    if (auto it = overrides.find(std::string(spec.name)); it != overrides.end()) spirv = it->second;
    if (spirv.empty()) return vk::Status::Fail(fmt::format("pass '{}': no kernel '{}.comp' was built", spec.name, spec.kernel));
    RS_TRY(p->ctx_->CreateKernel(std::string(spec.name), spirv, spec.bindings, FaultOf(faults, spec.name),
                                 p->kernels_[static_cast<std::size_t>(spec.id)], local_size));
  }
  p->raster_fault_ = FaultOf(faults, Pass(PassId::kRaster).name);
  out = std::move(p);
  return vk::Status::Ok();
}

vk::Status VulkanPasses::SetFaults(const Faults& faults) {
  for (const PassSpec& spec : kPasses) {
    const std::uint32_t fault = FaultOf(faults, spec.name);
    if (spec.graphics) {
      raster_fault_ = fault;
      continue;
    }
    vk::Kernel& k = kernels_[static_cast<std::size_t>(spec.id)];
    if (k.name().empty()) continue;  // not made (the grid build without 64-bit floats)
    RS_TRY(ctx_->SetKernelFault(k, fault));
  }
  return vk::Status::Ok();
}

namespace {
// Whole elements in a part of `bytes`, at least one.
std::size_t ElementsIn(std::size_t bytes, std::size_t bytes_per_element) {
  return std::max<std::size_t>(1, bytes / std::max<std::size_t>(bytes_per_element, 1));
}
}  // namespace

std::size_t VulkanPasses::PerPart(std::size_t bytes_per_element) const { return ElementsIn(SplitBytes(), bytes_per_element); }

std::size_t VulkanPasses::StreamPerPart(std::size_t bytes_per_element) const {
  return ElementsIn(std::min(SplitBytes(), kStreamPartBytes), bytes_per_element);
}

std::size_t VulkanPasses::SplitBytes() const { return static_cast<std::size_t>(ctx_->storage_limit()); }

}  // namespace rayspace::gpu_backend
