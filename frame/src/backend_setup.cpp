#include "rayspace/frame/backend_setup.h"

#include <algorithm>
#include <cstdio>

#include <fmt/format.h>

#include "rayspace/error.h"
#include "rayspace/layout.h"
#ifdef RAYSPACE_HAVE_VULKAN
#include "rayspace/gpu/backend.h"
#include "rayspace/gpu/kernel_check.h"
#endif
#include "rayspace/pass_registry.h"
#include "rayspace/frame/kernel_model.h"

namespace rayspace::app {

#ifdef RAYSPACE_HAVE_VULKAN
namespace {
struct VulkanOwner {
  std::unique_ptr<gpu_backend::VulkanPasses> gpu;
  std::unique_ptr<emu::FramePasses> frame;
  std::unique_ptr<emu::HierarchyPasses> hierarchy;
};

// Reads and checks every --kernel PASS=FILE.
gpu_backend::KernelOverrides LoadKernels(const KernelFiles& specs) {
  gpu_backend::KernelOverrides out;
  for (const std::string& spec : specs) {
    const auto eq = spec.find('=');
    if (eq == std::string::npos || eq == 0 || eq + 1 == spec.size()) ThrowInput("--kernel '{}': expected PASS=FILE", spec);
    const std::string pass = spec.substr(0, eq), file = spec.substr(eq + 1);
    const std::optional<PassId> id = FindPass(pass);
    if (!id) {
      std::string known;
      for (const PassSpec& p : kPasses)
        if (!p.graphics) known += (known.empty() ? "" : ", ") + std::string(p.name);
      ThrowInput("--kernel '{}': no pass named '{}'; passes with compute kernels: {}", spec, pass, known);
    }
    if (out.count(pass)) ThrowInput("--kernel '{}': pass '{}' is given twice", spec, pass);
    std::vector<std::uint32_t> spirv;
    if (vk::Status s = gpu_backend::LoadKernelFile(file, spirv, FindDataPaths(specs.data_prefix)); !s) ThrowInput("--kernel '{}': {}", spec, s.message);
    if (vk::Status s = gpu_backend::CheckKernel(Pass(*id), spirv); !s) ThrowInput("--kernel '{}': {}", spec, s.message);
    out[pass] = std::move(spirv);
  }
  return out;
}
}  // namespace
#endif


std::map<std::string, std::vector<std::uint32_t>> LoadKernelFiles(const KernelFiles& kernels) {
#ifdef RAYSPACE_HAVE_VULKAN
  return LoadKernels(kernels);
#else
  if (!kernels.empty()) ThrowInput("--kernel '{}': this build of rayspace has no Vulkan backend", kernels.front());
  return {};
#endif
}

void CheckKernelsRan(const Backend& backend, const KernelFiles& kernels) {
  if (kernels.empty() || !backend.launches) return;
  for (const std::string& spec : kernels) {
    const std::string pass = spec.substr(0, spec.find('='));
    const std::optional<PassId> id = FindPass(pass);
    if (!id || backend.launches(backend, *id) > 0) continue;
    std::string ran;
    for (const PassSpec& p : kPasses)
      if (!p.graphics && backend.launches(backend, p.id) > 0) ran += (ran.empty() ? "" : ", ") + std::string(p.name);
    const PassReach* reach = ReachOf(*id);
    std::string with;
    if (reach && !reach->example.empty())
      with = fmt::format(" (it runs with {}; for instance: render {})", reach->runs_with, reach->example);
    else if (reach)
      with = fmt::format(" (it runs with {})", reach->runs_with);
    ThrowInput("--kernel '{}': this run never launched pass '{}'{}, so the kernel was not tested; the run launched: {}", spec,
               pass, with, ran.empty() ? "no kernel" : ran);
  }
}

nlohmann::json ReportKernelCoverage(const Backend& backend, const KernelFiles& kernels) {
  if (kernels.empty() || !backend.coverage) return nullptr;
  nlohmann::json out = nlohmann::json::array();
  for (const std::string& spec : kernels) {
    const std::string pass = spec.substr(0, spec.find('='));
    const std::optional<PassId> id = FindPass(pass);
    if (!id) continue;
    const std::optional<sim::LineCoverage> c = backend.coverage(backend, *id);
    if (!c) continue;
    const char* unit = c->by_line ? "lines" : "instructions (no debug information)";
    std::string missed;
    for (std::size_t k = 0; k < c->missed.size() && k < 8; ++k) missed += (k ? ", " : "") + c->missed[k];
    if (c->missed.size() > 8) missed += fmt::format(" and {} more runs", c->missed.size() - 8);
    std::printf("  coverage of --kernel %s on the simulated GPU: %zu of %zu %s reached (%.0f %%)%s%s\n", pass.c_str(), c->reached, c->total,
                unit, c->total ? 100.0 * static_cast<double>(c->reached) / static_cast<double>(c->total) : 0.0,
                missed.empty() ? "" : "; never reached, so not tested by this run: ", missed.c_str());
    out.push_back({{"pass", pass}, {"by_line", c->by_line}, {"reached", c->reached}, {"total", c->total}, {"missed", c->missed}});
  }
  return out;
}

void CheckFrameFits(const Backend& backend, int width, int height, std::size_t slots, std::size_t triangles,
                    const std::string& size_from) {
  const std::size_t limit = backend.max_buffer_bytes;
  if (limit == 0) return;
  const std::size_t pixels = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  const std::size_t rays = pixels * std::max<std::size_t>(slots, 1);  // the largest batch: shadow rays
  const std::size_t pages = layout::kBufferPages;
  // Scene arrays are bound whole (the raster reads them too).
  if (triangles * sizeof(layout::Triangle) > limit)
    ThrowInput("scene: {} triangles take {} bytes per triangle array, more than one binding of '{}' holds ({} bytes)",
               triangles, triangles * sizeof(layout::Triangle), backend.device, limit);
  if (slots * sizeof(layout::Ray) > limit)
    ThrowInput("scene: {} light samples need {} bytes of shadow-ray slots per pixel, more than one binding of '{}' holds ({} bytes)",
               slots, slots * sizeof(layout::Ray), backend.device, limit);
  // Everything per pixel or per ray is split into parts or paged over kBufferPages bindings; the
  // paged ray array is the first to run out. The sort's scratch (about 8 bytes per ray) is bound
  // whole, and fits whenever the rays do, as long as kBufferPages < 8.
  static_assert(layout::kBufferPages * 8 < sizeof(layout::Ray));
  const std::size_t max_rays = pages * (limit / sizeof(layout::Ray));
  if (rays > max_rays)
    ThrowInput("{} {}x{}: {} rays per batch ({} light sample(s)) exceed the {} that {} bindings of {} bytes hold on '{}'; at most {} pixels fit",
               size_from, width, height, rays, slots, max_rays, pages, limit, backend.device, max_rays / std::max<std::size_t>(slots, 1));
}

void CheckGridBuild(const Backend& backend) {
  if (!backend.float64)
    ThrowInput("--algo grid: the Vulkan device '{}' lacks shaderFloat64 or shaderSignedZeroInfNanPreserveFloat64, which the grids' "
               "build kernels need (rayspace devices); use --backend emu",
               backend.device);
}

sim::DeviceConfig SimulatedConfig(const std::string& backends, std::uint32_t subgroup_size, const std::string& schedule,
                                  const std::string& sim_checks, const std::string& device_model, const std::string& subgroup_layout,
                                  std::uint64_t step_limit) {
  const bool sim_side = backends.find("sim") != std::string::npos;
  if (subgroup_size && !sim_side)
    ThrowInput("--subgroup-size {}: only the simulated GPU's subgroup size is chosen (--backends emu,sim, --backend sim); a Vulkan device has its own",
               subgroup_size);
  if (!sim_checks.empty() && !sim_side)
    ThrowInput("--sim-checks {}: only the simulated GPU runs these checkers (--backends emu,sim, --backend sim); a Vulkan device runs none", sim_checks);
  if (!device_model.empty() && !sim_side)
    ThrowInput("--device-model {}: only the simulated GPU's arithmetic is chosen (--backends emu,sim, --backend sim); a Vulkan device has its own",
               device_model);
  if (!subgroup_layout.empty() && !sim_side)
    ThrowInput("--subgroup-layout {}: only the simulated GPU's subgroup layout is chosen (--backends emu,sim, --backend sim); a Vulkan device has its own",
               subgroup_layout);
  if (step_limit && !sim_side)
    ThrowInput("--step-limit {}: only the simulated GPU has a step limit (--backends emu,sim, --backend sim)", step_limit);
  // The simulated GPU takes --schedule too: the order of its workgroups and subgroups.
  std::string error;
  const std::optional<sim::Checks> checks = sim::ParseChecks(sim_checks.empty() ? "all" : sim_checks, error);
  if (!checks) ThrowInput("--sim-checks {}: {}", sim_checks, error);
  const std::optional<sim::DeviceModelChoice> model = sim::ParseDeviceModel(device_model.empty() ? "lavapipe" : device_model, error);
  if (!model) ThrowInput("--device-model {}: {}", device_model, error);
  const std::optional<sim::SubgroupLayoutChoice> layout = sim::ParseSubgroupLayout(subgroup_layout.empty() ? "linear" : subgroup_layout, error);
  if (!layout) ThrowInput("--subgroup-layout {}: {}", subgroup_layout, error);
  return {.subgroup_size = subgroup_size ? subgroup_size : 8u,
          .schedule = ParseSchedule(schedule),
          .step_limit = step_limit ? step_limit : sim::DeviceConfig{}.step_limit,
          .checks = *checks,
          .arithmetic = *model,
          .layout = *layout};
}

Backend MakeBackend(const std::string& name, int device, int local_size, const std::map<std::string, std::uint32_t>& faults,
                    const TestLimits& limits, const KernelFiles& kernels, const sim::DeviceConfig& simulated) {
  Backend b;
  if (name == "emu" && !kernels.empty()) ThrowInput("--kernel '{}': user kernels run on --backend vulkan or sim", kernels.front());
  if (name == "emu") {
    b.device = "host";
    return b;
  }
  if (name != "vulkan" && name != "sim") ThrowInput("--backend '{}': expected emu, sim or vulkan", name);
#ifdef RAYSPACE_HAVE_VULKAN
  auto owner = std::make_shared<VulkanOwner>();
  const gpu_backend::KernelOverrides overrides = LoadKernels(kernels);
  // sim: the same host code over the simulated device (vk::Context::CreateSimulated).
  if (name == "sim") device = vk::Context::kSimulatedDevice;
  if (vk::Status s = gpu_backend::VulkanPasses::Create(device, faults, owner->gpu, static_cast<std::uint32_t>(local_size), overrides,
                                                       simulated);
      !s) {
    // "--device N: ...", "--validate: ...": an option this machine cannot honour, not a failure
    if (s.message.rfind("--", 0) == 0) ThrowInput("{}", s.message);
    throw std::runtime_error("Vulkan: " + s.message);
  }
  owner->gpu->LimitForTesting(limits.storage_bytes, limits.groups_x);
  owner->frame = gpu_backend::MakeVulkanFramePasses(*owner->gpu);
  owner->hierarchy = gpu_backend::MakeVulkanHierarchyPasses(*owner->gpu);
  b.name = name;
  b.device = owner->gpu->context().device_name();
  b.max_buffer_bytes = owner->gpu->SplitBytes();
  b.subgroup_size = owner->gpu->context().subgroup_size();
  b.correctly_rounded = owner->gpu->context().correctly_rounded_floats();
  b.float64 = owner->gpu->context().float64();
  b.frame = owner->frame.get();
  b.hierarchy = owner->hierarchy.get();
  b.owner = owner;
  b.extra_dispatches = [](const Backend& be) {
    return static_cast<const VulkanOwner*>(be.owner.get())->gpu->extra_dispatches();
  };
  b.paged_arrays = [](const Backend& be) { return static_cast<const VulkanOwner*>(be.owner.get())->gpu->paged_arrays(); };
  b.set_faults = [](const Backend& be, const std::map<std::string, std::uint32_t>& f) {
    gpu_backend::VulkanPasses& gpu = *static_cast<const VulkanOwner*>(be.owner.get())->gpu;
    if (vk::Status s = gpu.SetFaults(f); !s) throw std::runtime_error("Vulkan: " + s.message);
    gpu.ResetCounts();
  };
  b.launches = [](const Backend& be, PassId id) { return static_cast<const VulkanOwner*>(be.owner.get())->gpu->launches(id); };
  if (name == "sim")
    b.coverage = [](const Backend& be, PassId id) { return static_cast<const VulkanOwner*>(be.owner.get())->gpu->coverage(id); };
  b.folded_launches = [](const Backend& be) {
    return static_cast<const VulkanOwner*>(be.owner.get())->gpu->context().folded_launches();
  };
  return b;
#else
  (void)device;
  (void)local_size;
  (void)faults;
  (void)limits;
  (void)kernels;
  (void)simulated;
  ThrowInput("--backend vulkan: this build of rayspace has no Vulkan backend (configured with RAYSPACE_VULKAN=OFF, or AUTO "
             "without the Vulkan loader, glslc or SPIRV-Cross)");
#endif
}

}  // namespace rayspace::app
