#include "rayspace/gpu/requirements.h"

#include <fmt/format.h>

#include <algorithm>

#include <spirv/unified1/spirv.hpp11>

#include "rayspace/contract.h"
#include "rayspace/gpu/passes.h"
#include "rayspace/gpu/raster.h"
#include "rayspace/gpu/vulkan.h"
#include "rayspace/pass_registry.h"
#include "rayspace/settings.h"

namespace rayspace::vk {
namespace {


// The shared memory the kernels declare at most (sort.comp: wg_tile, the scatter's marks and bins).
constexpr std::uint32_t kSharedBytes = (layout::kMaxLocalSize + 256 * layout::kSortRankWords + 256) * 4;
// The raster's attachment formats (raster.h), as the requirements below name them.
static_assert(gpu_backend::kRasterDepthFormat == VK_FORMAT_D32_SFLOAT &&
                  gpu_backend::kRasterColorFormats[0] == VK_FORMAT_R32G32B32A32_SFLOAT &&
                  gpu_backend::kRasterColorFormats[3] == VK_FORMAT_R32G32B32A32_SFLOAT &&
                  gpu_backend::kRasterColorFormats[4] == VK_FORMAT_R32_UINT && std::size(gpu_backend::kRasterColorFormats) == 5,
              "the raster's formats changed: update the format requirements");

std::uint32_t MaxBindings() {
  std::uint32_t m = 0;
  for (const PassSpec& p : kPasses) m = std::max(m, p.bindings);
  return m;
}

std::uint32_t MaxPushBytes() {
  std::uint32_t m = 0;
  for (const PassSpec& p : kPasses) m = std::max(m, p.push_bytes);
  return m;
}

const char* TypeName(VkPhysicalDeviceType t) {
  switch (t) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return "discrete GPU";
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return "integrated GPU";
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return "virtual GPU";
    case VK_PHYSICAL_DEVICE_TYPE_CPU: return "CPU";
    default: return "other";
  }
}

const char* YesNo(bool b) { return b ? "supported" : "not supported"; }

class Checker {
 public:
  explicit Checker(const Lacks& lacking) : lacking_(lacking) {}
  void Feature(const std::string& name, const std::string& why, bool have, bool optional = false) {
    have = have && !lacking_.count(name);
    out_.push_back({name, why, "supported", YesNo(have), have, optional});
  }
  void Version(const std::string& name, const std::string& why, std::uint32_t need, std::uint32_t have) {
    if (auto it = lacking_.find(name); it != lacking_.end()) have = static_cast<std::uint32_t>(it->second);
    const auto str = [](std::uint32_t v) { return fmt::format("{}.{}", VK_API_VERSION_MAJOR(v), VK_API_VERSION_MINOR(v)); };
    out_.push_back({name, why, ">= " + str(need), str(have), have >= need});
  }
  void Limit(const std::string& name, const std::string& why, std::uint64_t need, std::uint64_t have) {
    if (auto it = lacking_.find(name); it != lacking_.end()) have = it->second;
    out_.push_back({name, why, fmt::format(">= {}", need), std::to_string(have), have >= need});
  }
  std::vector<Requirement> Take() { return std::move(out_); }

 private:
  const Lacks& lacking_;
  std::vector<Requirement> out_;
};

bool FormatHas(VkPhysicalDevice d, VkFormat f, VkFormatFeatureFlags need) {
  VkFormatProperties p;
  vkGetPhysicalDeviceFormatProperties(d, f, &p);
  return (p.optimalTilingFeatures & need) == need;
}

void CheckFormats(Checker& c, VkPhysicalDevice d) {
  constexpr VkFormatFeatureFlags kColor = VK_FORMAT_FEATURE_COLOR_ATTACHMENT_BIT | VK_FORMAT_FEATURE_TRANSFER_SRC_BIT;
  c.Feature("VK_FORMAT_D32_SFLOAT", "raster: the depth attachment, copied out",
            FormatHas(d, gpu_backend::kRasterDepthFormat, VK_FORMAT_FEATURE_DEPTH_STENCIL_ATTACHMENT_BIT | VK_FORMAT_FEATURE_TRANSFER_SRC_BIT));
  c.Feature("VK_FORMAT_R32G32B32A32_SFLOAT", "raster: four G-buffer colour attachments, copied out", FormatHas(d, gpu_backend::kRasterColorFormats[0], kColor));
  c.Feature("VK_FORMAT_R32_UINT", "raster: the primitive-id colour attachment, copied out", FormatHas(d, gpu_backend::kRasterColorFormats[4], kColor));
}

// The subgroup features as the kernels' SPIR-V declares them: a row per feature, naming the
// kernels; optional, since a device without one runs every kernel that does not declare it (and
// those are refused at creation, naming it).
void CheckSubgroups(Checker& c, const VkPhysicalDeviceSubgroupProperties& sub) {
  c.Limit("subgroupSize", "the subgroup kernels' grids (a subgroup per node or component; any size 1-128 gives the same bits)", 1,
          sub.subgroupSize);
  std::map<VkSubgroupFeatureFlags, std::string> users;
  VkSubgroupFeatureFlags any = 0;
  for (std::string_view k : gpu_backend::BuiltinKernelNames()) {
    const VkSubgroupFeatureFlags f = SubgroupFeaturesOf(gpu_backend::BuiltinKernel(k));
    any |= f;
    for (VkSubgroupFeatureFlags bit = 1; bit <= f; bit <<= 1)
      if (f & bit) users[bit] += fmt::format("{}{}", users[bit].empty() ? "" : ", ", k);
  }
  const bool compute = (sub.supportedStages & VK_SHADER_STAGE_COMPUTE_BIT) != 0;
  c.Feature("subgroupSupportedStages", "every kernel that uses subgroups: subgroup operations in compute", compute || any == 0);
  for (const auto& [bit, kernels] : users)
    c.Feature(SubgroupFeatureName(bit), "kernels " + kernels, compute && (sub.supportedOperations & bit) != 0, true);
}

bool HasGraphicsComputeQueue(VkPhysicalDevice d) {
  std::uint32_t n = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(d, &n, nullptr);
  std::vector<VkQueueFamilyProperties> fams(n);
  vkGetPhysicalDeviceQueueFamilyProperties(d, &n, fams.data());
  for (const VkQueueFamilyProperties& f : fams)
    if ((f.queueFlags & VK_QUEUE_GRAPHICS_BIT) && (f.queueFlags & VK_QUEUE_COMPUTE_BIT)) return true;
  return false;
}

}  // namespace

const Lacks& DeviceLacks() { return CurrentSettings().device_lacks; }
std::string UnknownLack(const std::vector<Requirement>& reqs) {
  for (const auto& [name, value] : DeviceLacks())
    if (!Fakeable(name, reqs)) return name;
  return {};
}

bool Fakeable(const std::string& name, const std::vector<Requirement>& reqs) {
  if (name == "maxComputeWorkGroupInvocations" || name == "maxComputeWorkGroupSize[0]" || name == "maxMemoryAllocationCount" ||
      name == "mappableDeviceLocal")
    return true;
  return std::any_of(reqs.begin(), reqs.end(), [&](const Requirement& r) { return r.name == name; });
}

std::uint64_t FakedLimit(const std::string& name, std::uint64_t have) {
  auto it = DeviceLacks().find(name);
  return it == DeviceLacks().end() ? have : it->second;
}

DeviceInfo QueryDevice(VkPhysicalDevice d) {
  DeviceInfo info;
  VkPhysicalDeviceFeatures2 f2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
  f2.pNext = &info.features12;
  vkGetPhysicalDeviceFeatures2(d, &f2);
  info.features = f2.features;
  info.float_controls.pNext = &info.subgroup;
  info.subgroup.pNext = &info.driver;
  VkPhysicalDeviceProperties2 p2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
  p2.pNext = &info.float_controls;
  vkGetPhysicalDeviceProperties2(d, &p2);
  info.props = p2.properties;
  info.features12.pNext = info.float_controls.pNext = info.subgroup.pNext = info.driver.pNext = nullptr;
  return info;
}

std::vector<Requirement> CheckRequirements(VkPhysicalDevice d, const Lacks& lacking) {
  const DeviceInfo info = QueryDevice(d);
  const VkPhysicalDeviceProperties& props = info.props;
  const VkPhysicalDeviceVulkan12Features& f12 = info.features12;
  const VkPhysicalDeviceFloatControlsProperties& fc = info.float_controls;
  const VkPhysicalDeviceSubgroupProperties& sub = info.subgroup;
  const VkPhysicalDeviceLimits& lim = props.limits;

  Checker c(lacking);
  c.Version("apiVersion", "every pass (Vulkan 1.2 features and properties)", VK_API_VERSION_1_2, props.apiVersion);
  c.Feature("shaderInt64", "intersect, shade (64-bit hit records and sums)", info.features.shaderInt64);
  c.Feature("shaderFloat64", "grid.count, grid.emit only (the grids' binning in double, as the host's)", info.features.shaderFloat64, true);
  c.Feature("shaderSignedZeroInfNanPreserveFloat64", "grid.count, grid.emit only (no (a - b) + b -> a folding in double)",
            fc.shaderSignedZeroInfNanPreserveFloat64, true);
  c.Feature("shaderBufferInt64Atomics", "intersect, shade (atomicMin / atomicAdd on 64-bit words)", f12.shaderBufferInt64Atomics);
  c.Feature("shaderSignedZeroInfNanPreserveFloat32", "every kernel (SignedZeroInfNanPreserve: no a - a -> 0 folding)",
            fc.shaderSignedZeroInfNanPreserveFloat32);
  CheckSubgroups(c, sub);
  c.Feature("graphicsComputeQueue", "raster and the compute passes: one queue family with both", HasGraphicsComputeQueue(d));
  CheckFormats(c, d);
  c.Limit("maxColorAttachments", "raster (five G-buffer targets)", 5, lim.maxColorAttachments);
  c.Limit("maxFragmentOutputAttachments", "raster (five G-buffer targets)", 5, lim.maxFragmentOutputAttachments);
  c.Limit("maxPerStageDescriptorStorageBuffers", "intersect (three arrays and five paged arrays of four)", MaxBindings(),
          lim.maxPerStageDescriptorStorageBuffers);
  c.Limit("maxPushConstantsSize", "traverse.compact (the largest push block)", MaxPushBytes(), lim.maxPushConstantsSize);
  c.Limit("maxComputeSharedMemorySize", "sort (wg_tile, marks and bins at the largest local size)", kSharedBytes,
          lim.maxComputeSharedMemorySize);
  return c.Take();
}

// Discrete GPUs first, then integrated, virtual, other, CPU; among equals, one that meets every
// requirement; then the lowest index.
int PreferredDevice(const std::vector<VkPhysicalDevice>& devs) {
  const auto rank = [](VkPhysicalDeviceType t) {
    switch (t) {
      case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return 0;
      case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return 1;
      case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return 2;
      case VK_PHYSICAL_DEVICE_TYPE_CPU: return 4;
      default: return 3;
    }
  };
  int best = 0, best_score = 1 << 30;
  for (std::size_t i = 0; i < devs.size(); ++i) {
    VkPhysicalDeviceProperties p;
    vkGetPhysicalDeviceProperties(devs[i], &p);
    const bool ok = Unmet(CheckRequirements(devs[i], DeviceLacks())).empty();
    const int score = rank(p.deviceType) * 2 + (ok ? 0 : 1);
    if (score < best_score) best = static_cast<int>(i), best_score = score;
  }
  return best;
}

std::vector<DeviceReport> DescribeDevices(int& preferred) {
  std::vector<DeviceReport> out;
  preferred = -1;
  VkInstance inst = VK_NULL_HANDLE;
  if (!CreateInstance(inst, nullptr)) return out;
  std::uint32_t n = 0;
  vkEnumeratePhysicalDevices(inst, &n, nullptr);
  std::vector<VkPhysicalDevice> devs(n);
  vkEnumeratePhysicalDevices(inst, &n, devs.data());
  for (std::uint32_t i = 0; i < n; ++i) {
    const DeviceInfo info = QueryDevice(devs[i]);
    DeviceReport r;
    r.index = static_cast<int>(i);
    r.name = info.props.deviceName;
    r.type = TypeName(info.props.deviceType);
    r.driver = fmt::format("{} {}", info.driver.driverName, info.driver.driverInfo);
    r.driver_id = info.driver.driverID;
    r.requirements = CheckRequirements(devs[i], DeviceLacks());
    r.denorm_preserve = info.float_controls.shaderDenormPreserveFloat32;
    r.denorm_flush = info.float_controls.shaderDenormFlushToZeroFloat32;
    r.round_to_nearest = info.float_controls.shaderRoundingModeRTEFloat32;
    out.push_back(std::move(r));
  }
  if (n) preferred = PreferredDevice(devs);
  vkDestroyInstance(inst, nullptr);
  return out;
}

VkSubgroupFeatureFlags SubgroupFeaturesOf(std::span<const std::uint32_t> spirv) {
  VkSubgroupFeatureFlags f = 0;
  if (spirv.size() < 5 || spirv[0] != spv::MagicNumber) return f;
  for (std::size_t at = 5; at < spirv.size();) {
    const std::uint32_t words = spirv[at] >> 16, op = spirv[at] & 0xffffu;
    if (words == 0 || at + words > spirv.size()) break;
    if (op == static_cast<std::uint32_t>(spv::Op::OpCapability) && words == 2) {
      switch (static_cast<spv::Capability>(spirv[at + 1])) {
        case spv::Capability::GroupNonUniform: f |= VK_SUBGROUP_FEATURE_BASIC_BIT; break;
        case spv::Capability::GroupNonUniformVote: f |= VK_SUBGROUP_FEATURE_VOTE_BIT; break;
        case spv::Capability::GroupNonUniformArithmetic: f |= VK_SUBGROUP_FEATURE_ARITHMETIC_BIT; break;
        case spv::Capability::GroupNonUniformBallot: f |= VK_SUBGROUP_FEATURE_BALLOT_BIT; break;
        case spv::Capability::GroupNonUniformShuffle: f |= VK_SUBGROUP_FEATURE_SHUFFLE_BIT; break;
        case spv::Capability::GroupNonUniformShuffleRelative: f |= VK_SUBGROUP_FEATURE_SHUFFLE_RELATIVE_BIT; break;
        case spv::Capability::GroupNonUniformClustered: f |= VK_SUBGROUP_FEATURE_CLUSTERED_BIT; break;
        case spv::Capability::GroupNonUniformQuad: f |= VK_SUBGROUP_FEATURE_QUAD_BIT; break;
        default: break;
      }
    } else if (op != static_cast<std::uint32_t>(spv::Op::OpNop)) {
      break;  // capabilities come first in a module
    }
    at += words;
  }
  return f;
}

std::string SubgroupFeatureName(VkSubgroupFeatureFlags bit) {
  switch (bit) {
    case VK_SUBGROUP_FEATURE_BASIC_BIT: return "VK_SUBGROUP_FEATURE_BASIC_BIT";
    case VK_SUBGROUP_FEATURE_VOTE_BIT: return "VK_SUBGROUP_FEATURE_VOTE_BIT";
    case VK_SUBGROUP_FEATURE_ARITHMETIC_BIT: return "VK_SUBGROUP_FEATURE_ARITHMETIC_BIT";
    case VK_SUBGROUP_FEATURE_BALLOT_BIT: return "VK_SUBGROUP_FEATURE_BALLOT_BIT";
    case VK_SUBGROUP_FEATURE_SHUFFLE_BIT: return "VK_SUBGROUP_FEATURE_SHUFFLE_BIT";
    case VK_SUBGROUP_FEATURE_SHUFFLE_RELATIVE_BIT: return "VK_SUBGROUP_FEATURE_SHUFFLE_RELATIVE_BIT";
    case VK_SUBGROUP_FEATURE_CLUSTERED_BIT: return "VK_SUBGROUP_FEATURE_CLUSTERED_BIT";
    case VK_SUBGROUP_FEATURE_QUAD_BIT: return "VK_SUBGROUP_FEATURE_QUAD_BIT";
    default: return fmt::format("subgroup feature 0x{:x}", bit);
  }
}

VkSubgroupFeatureFlags ComputeSubgroupFeatures(const DeviceInfo& info) {
  if (!(info.subgroup.supportedStages & VK_SHADER_STAGE_COMPUTE_BIT) || DeviceLacks().count("subgroupSupportedStages")) return 0;
  VkSubgroupFeatureFlags f = info.subgroup.supportedOperations;
  for (VkSubgroupFeatureFlags bit = 1; bit != 0 && bit <= f; bit <<= 1)
    if ((f & bit) && DeviceLacks().count(SubgroupFeatureName(bit))) f &= ~bit;
  return f;
}

std::string Unmet(const std::vector<Requirement>& reqs) {
  std::string s;
  for (const Requirement& r : reqs)
    if (!r.met && !r.optional) s += fmt::format("{}{} (needed by {}: {}; the device: {})", s.empty() ? "" : "; ", r.name, r.why, r.need, r.have);
  return s;
}

bool HasFloat64(VkPhysicalDevice device) {
  bool has = true;
  for (const Requirement& r : CheckRequirements(device, DeviceLacks()))
    if (r.name == "shaderFloat64" || r.name == "shaderSignedZeroInfNanPreserveFloat64") has = has && r.met;
  return has;
}

}  // namespace rayspace::vk
