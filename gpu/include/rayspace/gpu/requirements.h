// What rayspace needs of a Vulkan device, checked before anything is created on it: the API version,
// the features and properties the kernels declare, the formats and limits the passes use. Each
// requirement has a name (the Vulkan feature, property or limit, as the spec spells it), what is
// needed and what the device has. `rayspace devices` prints them; Context::Create refuses a device
// that lacks any, naming each.
#pragma once
#include <cstdint>
#include <map>
#include <span>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

namespace rayspace::vk {

// What rayspace reads of a device, in one query (the pNext chains are cut after it).
struct DeviceInfo {
  DeviceInfo() {
    features12.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES;
    float_controls.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FLOAT_CONTROLS_PROPERTIES;
    subgroup.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SUBGROUP_PROPERTIES;
    driver.sType = VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES;
  }
  VkPhysicalDeviceProperties props{};
  VkPhysicalDeviceFeatures features{};
  VkPhysicalDeviceVulkan12Features features12{};
  VkPhysicalDeviceFloatControlsProperties float_controls{};
  VkPhysicalDeviceSubgroupProperties subgroup{};
  VkPhysicalDeviceDriverProperties driver{};
};
DeviceInfo QueryDevice(VkPhysicalDevice device);

struct Requirement {
  std::string name;  // e.g. "shaderInt64", "maxPerStageDescriptorStorageBuffers"
  std::string why;   // which pass or part needs it
  std::string need;  // e.g. "supported", ">= 23"
  std::string have;  // what the device reports
  bool met = false;
  // Needed by some passes only (`why` names them): a device without it runs every other pass, and
  // those passes fail naming it.
  bool optional = false;
};

// Test use (`--device-lacks NAME[=VALUE]`): requirement names a device is to look as if it lacked, a
// feature as unsupported, a limit or version as VALUE (default 0), so that each refusal can be tested on
// any device. maxComputeWorkGroupInvocations and maxComputeWorkGroupSize[0] may be named too: they
// are checked against --local-size when a kernel is created.
using Lacks = std::map<std::string, std::uint64_t>;

// Every requirement, evaluated on `device` as `lacking` makes it look.
std::vector<Requirement> CheckRequirements(VkPhysicalDevice device, const Lacks& lacking);

// Settings::device_lacks (a test hook, --device-lacks): devices look as if they lacked these.
const Lacks& DeviceLacks();
// Whether `name` may be given to --device-lacks: a requirement's name, or a limit checked elsewhere
// (the workgroup limits against --local-size, maxMemoryAllocationCount by the memory pool), or
// mappableDeviceLocal: no device-local memory the host can map, so storage buffers are staged.
bool Fakeable(const std::string& name, const std::vector<Requirement>& reqs);
// The first DeviceLacks() name that is not Fakeable, or "".
std::string UnknownLack(const std::vector<Requirement>& reqs);
// A limit as the device reports it, or as DeviceLacks() fakes it.
std::uint64_t FakedLimit(const std::string& name, std::uint64_t have);

// The subgroup features a kernel declares: its OpCapability GroupNonUniform* as Vulkan's
// VkSubgroupFeatureFlagBits (a module that is not SPIR-V declares none).
VkSubgroupFeatureFlags SubgroupFeaturesOf(std::span<const std::uint32_t> spirv);
// A feature's requirement name as the spec spells its bit, "VK_SUBGROUP_FEATURE_VOTE_BIT".
std::string SubgroupFeatureName(VkSubgroupFeatureFlags bit);
// The subgroup features a device (as QueryDevice read it) offers in compute, less the ones
// DeviceLacks() names.
VkSubgroupFeatureFlags ComputeSubgroupFeatures(const DeviceInfo& info);

// The device to use without --device: discrete GPUs first, then integrated, virtual, other and CPU;
// among equals one that meets every requirement; then the lowest index.
int PreferredDevice(const std::vector<VkPhysicalDevice>& devices);

// Every device the loader lists, with its requirements (as DeviceLacks() makes them look), for
// `rayspace devices`; `preferred` receives PreferredDevice's choice (-1: no device).
struct DeviceReport {
  int index = 0;
  std::string name, type, driver;
  VkDriverId driver_id{};
  std::vector<Requirement> requirements;
  // What the device promises about 32-bit float arithmetic beyond Vulkan's minimum (informational:
  // the device model of non-lavapipe GPUs is built on these): denormals preserved or flushed on
  // request, round-to-nearest-even on request.
  bool denorm_preserve = false, denorm_flush = false, round_to_nearest = false;
};
std::vector<DeviceReport> DescribeDevices(int& preferred);

// "shaderInt64 (needed by intersect and shade: supported; the device: not supported); ..." for the
// unmet ones that are not optional, or "" when every such requirement is met.
std::string Unmet(const std::vector<Requirement>& reqs);
// Whether the device (as DeviceLacks() makes it look) has what the grids' build kernels need:
// shaderFloat64 and shaderSignedZeroInfNanPreserveFloat64 (optional requirements).
bool HasFloat64(VkPhysicalDevice device);

}  // namespace rayspace::vk
