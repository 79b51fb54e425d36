#include "rayspace/gpu/vulkan.h"

#include <fmt/format.h>

#include <algorithm>
#include <cstdio>
#include <cstring>

#include "rayspace/contract.h"
#include "rayspace/gpu/float_controls.h"
#include "rayspace/gpu/memory.h"
#include "rayspace/gpu/requirements.h"
#include "rayspace/gpu/validation.h"
#include "rayspace/sim/executor.h"
#include "rayspace/sim/module_tools.h"
#include "rayspace/sim/program.h"
#include "rayspace/settings.h"

namespace rayspace::vk {

const char* ResultName(VkResult r) {
  switch (r) {
#define RS_CASE(x) \
  case x: return #x;
    RS_CASE(VK_SUCCESS)
    RS_CASE(VK_NOT_READY)
    RS_CASE(VK_TIMEOUT)
    RS_CASE(VK_ERROR_OUT_OF_HOST_MEMORY)
    RS_CASE(VK_ERROR_OUT_OF_DEVICE_MEMORY)
    RS_CASE(VK_ERROR_INITIALIZATION_FAILED)
    RS_CASE(VK_ERROR_DEVICE_LOST)
    RS_CASE(VK_ERROR_MEMORY_MAP_FAILED)
    RS_CASE(VK_ERROR_LAYER_NOT_PRESENT)
    RS_CASE(VK_ERROR_EXTENSION_NOT_PRESENT)
    RS_CASE(VK_ERROR_FEATURE_NOT_PRESENT)
    RS_CASE(VK_ERROR_INCOMPATIBLE_DRIVER)
    RS_CASE(VK_ERROR_TOO_MANY_OBJECTS)
    RS_CASE(VK_ERROR_FORMAT_NOT_SUPPORTED)
    RS_CASE(VK_ERROR_OUT_OF_POOL_MEMORY)
    RS_CASE(VK_ERROR_INVALID_SHADER_NV)
#undef RS_CASE
    default: return "VkResult";
  }
}

namespace {

// A failed call, or a call after which the validation layer has reported (the report may concern
// commands recorded since the last check), returns a failed Status naming the call.
#define RS_VK(call)                                                                               \
  do {                                                                                            \
    const VkResult rs_r = (call);                                                                 \
    if (rs_r != VK_SUCCESS) return Status::Fail(#call, rs_r);                                     \
    if (ValidationPending())                                                                      \
      return Status::Fail(fmt::format("{}: {}", std::string(#call).substr(0, std::string(#call).find('(')), \
                                      TakeValidationMessages()));                                 \
  } while (0)

Status CreateModule(VkDevice device, std::span<const std::uint32_t> spirv, VkShaderModule& out) {
  VkShaderModuleCreateInfo smci{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
  smci.codeSize = spirv.size_bytes();
  smci.pCode = spirv.data();
  RS_VK(vkCreateShaderModule(device, &smci, nullptr, &out));
  return Status::Ok();
}

// A set layout of `bindings` storage buffers seen by `stages`, and a pipeline layout over that one
// set with `push_bytes` of push constants (none when 0).
Status CreateLayouts(VkDevice device, std::uint32_t bindings, VkShaderStageFlags stages, std::uint32_t push_bytes,
                     VkDescriptorSetLayout& set_layout, VkPipelineLayout& layout) {
  std::vector<VkDescriptorSetLayoutBinding> b(bindings);
  for (std::uint32_t i = 0; i < bindings; ++i) b[i] = {i, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, stages, nullptr};
  VkDescriptorSetLayoutCreateInfo dl{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
  dl.bindingCount = bindings;
  dl.pBindings = b.data();
  RS_VK(vkCreateDescriptorSetLayout(device, &dl, nullptr, &set_layout));
  VkPushConstantRange pcr{stages, 0, push_bytes};
  VkPipelineLayoutCreateInfo pl{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
  pl.setLayoutCount = 1;
  pl.pSetLayouts = &set_layout;
  pl.pushConstantRangeCount = push_bytes ? 1 : 0;
  pl.pPushConstantRanges = push_bytes ? &pcr : nullptr;
  RS_VK(vkCreatePipelineLayout(device, &pl, nullptr, &layout));
  return Status::Ok();
}

}  // namespace

Status Status::Fail(const std::string& call, VkResult r) {
  std::string name = call.substr(0, call.find('('));
  std::string message = fmt::format("{} failed: {} ({})", name, ResultName(r), static_cast<int>(r));
  Status s{false, r, std::move(name), std::move(message), {}, {}};
  s.device_fault = true;
  return s;
}

Buffer& Buffer::operator=(Buffer&& o) noexcept {
  std::swap(ctx_, o.ctx_);
  std::swap(device_, o.device_);
  std::swap(buffer_, o.buffer_);
  std::swap(pool_, o.pool_);
  std::swap(range_, o.range_);
  std::swap(size_, o.size_);
  std::swap(guard_, o.guard_);
  std::swap(mapped_, o.mapped_);
  std::swap(observed_, o.observed_);
  std::swap(host_, o.host_);
  return *this;
}

Status Buffer::Write(const void* src, std::size_t bytes) {
  if (bytes > size_) return Status::Fail(fmt::format("a write of {} bytes into a buffer of {}", bytes, size_));
  if (mapped_) {
    if (bytes) std::memcpy(mapped_, src, bytes);
  } else {
    RS_TRY(ctx_->Stage(*this, const_cast<void*>(src), bytes, /*to_device=*/true));
  }
  if (observed_ && ctx_->observer()) ctx_->observer()->BufferWritten(*this, src, bytes);
  return Status::Ok();
}

Status Buffer::Zero() {
  if (mapped_) {
    std::memset(mapped_, 0, size_);
  } else {
    std::vector<char> zeros(size_, 0);
    RS_TRY(ctx_->Stage(*this, zeros.data(), size_, /*to_device=*/true));
  }
  if (observed_ && ctx_->observer()) ctx_->observer()->BufferWritten(*this, nullptr, size_);
  return Status::Ok();
}

Status Buffer::Read(void* dst, std::size_t bytes) const {
  if (bytes > size_) return Status::Fail(fmt::format("a read of {} bytes from a buffer of {}", bytes, size_));
  if (mapped_) {
    if (bytes) std::memcpy(dst, mapped_, bytes);
  } else {
    RS_TRY(ctx_->Stage(*this, dst, bytes, /*to_device=*/false));
  }
  if (observed_ && ctx_->observer()) ctx_->observer()->BufferRead(*this, dst, bytes);
  return Status::Ok();
}

bool Buffer::GuardChanged(std::size_t& word, std::uint32_t& value) const {
  if (!guard_ || !mapped_) return false;
  const auto* bytes = static_cast<const std::uint8_t*>(mapped_) + size_;
  for (std::size_t k = 0; k < guard_ / 4; ++k) {
    std::memcpy(&value, bytes + 4 * k, 4);
    if (value != kGuardWord) {
      word = k;
      return true;
    }
  }
  return false;
}

Buffer::~Buffer() {
  if (host_) {
    if (observed_ && ctx_->observer()) ctx_->observer()->BufferDestroyed(*this);
    return;
  }
  if (!device_) return;
  if (observed_ && ctx_->observer()) ctx_->observer()->BufferDestroyed(*this);
  vkDestroyBuffer(device_, buffer_, nullptr);
  if (pool_) pool_->Release(range_);
}

std::optional<sim::LineCoverage> Kernel::coverage() const {
  if (!program_ || coverage_.empty()) return std::nullopt;
  return sim::CoverageOf(*program_, coverage_);
}

Kernel::~Kernel() {
  if (!device_) return;
  vkDestroyPipeline(device_, pipeline_, nullptr);
  vkDestroyPipelineLayout(device_, layout_, nullptr);
  vkDestroyDescriptorSetLayout(device_, set_layout_, nullptr);
  vkDestroyShaderModule(device_, module_, nullptr);
}

Image& Image::operator=(Image&& o) noexcept {
  std::swap(device_, o.device_);
  std::swap(image_, o.image_);
  std::swap(pool_, o.pool_);
  std::swap(range_, o.range_);
  std::swap(view_, o.view_);
  std::swap(aspect_, o.aspect_);
  std::swap(width_, o.width_);
  std::swap(height_, o.height_);
  return *this;
}

Image::~Image() {
  if (!device_) return;
  vkDestroyImageView(device_, view_, nullptr);
  vkDestroyImage(device_, image_, nullptr);
  if (pool_) pool_->Release(range_);
}

Graphics::~Graphics() {
  if (!device_) return;
  vkDestroyPipeline(device_, pipeline_, nullptr);
  vkDestroyFramebuffer(device_, framebuffer_, nullptr);
  vkDestroyRenderPass(device_, pass_, nullptr);
  vkDestroyPipelineLayout(device_, layout_, nullptr);
  vkDestroyDescriptorSetLayout(device_, set_layout_, nullptr);
  vkDestroyShaderModule(device_, frag_, nullptr);
  vkDestroyShaderModule(device_, vert_, nullptr);
}

std::vector<std::string> Context::ListDevices() {
  std::vector<std::string> out;
  int preferred = -1;
  for (const DeviceReport& d : DescribeDevices(preferred)) out.push_back(d.name);
  return out;
}

// The limits and names of the chosen device that the passes and reports read.
void Context::ReadProperties() {
  const DeviceInfo info = QueryDevice(physical_);
  const VkPhysicalDeviceLimits& lim = info.props.limits;
  device_name_ = info.props.deviceName;
  subgroup_features_ = ComputeSubgroupFeatures(info);
  float_controls_ = {info.float_controls.shaderDenormPreserveFloat32 != VK_FALSE, info.float_controls.shaderRoundingModeRTEFloat32 != VK_FALSE};
  max_storage_range_ = lim.maxStorageBufferRange;
  storage_limit_ = max_storage_range_;
  max_groups_[0] = lim.maxComputeWorkGroupCount[0];
  max_groups_[1] = lim.maxComputeWorkGroupCount[1];
  max_stage_storage_buffers_ = lim.maxPerStageDescriptorStorageBuffers;
  max_invocations_ = static_cast<std::uint32_t>(FakedLimit("maxComputeWorkGroupInvocations", lim.maxComputeWorkGroupInvocations));
  max_size_x_ = static_cast<std::uint32_t>(FakedLimit("maxComputeWorkGroupSize[0]", lim.maxComputeWorkGroupSize[0]));
  max_image_side_ = lim.maxImageDimension2D;
  max_allocations_ = static_cast<std::uint32_t>(FakedLimit("maxMemoryAllocationCount", lim.maxMemoryAllocationCount));
  subgroup_size_ = std::max(info.subgroup.subgroupSize, 1u);
  driver_ = fmt::format("{} {}", info.driver.driverName, info.driver.driverInfo);
  driver_id_ = info.driver.driverID;
  vkGetPhysicalDeviceMemoryProperties(physical_, &memory_);
}

// One compute queue, the features the kernels need, and a command pool.
Status Context::CreateDevice() {
  std::uint32_t nf = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(physical_, &nf, nullptr);
  std::vector<VkQueueFamilyProperties> fams(nf);
  vkGetPhysicalDeviceQueueFamilyProperties(physical_, &nf, fams.data());
  bool found = false;
  for (std::uint32_t i = 0; i < nf && !found; ++i)
    if ((fams[i].queueFlags & VK_QUEUE_COMPUTE_BIT) && (fams[i].queueFlags & VK_QUEUE_GRAPHICS_BIT)) {
      family_ = i;  // the raster and the compute passes share one queue
      found = true;
    }
  if (!found) return Status::Fail(fmt::format("Vulkan device '{}' has no queue family with graphics and compute", device_name_));

  VkPhysicalDeviceFeatures features{};
  features.shaderInt64 = VK_TRUE;
  // The grids' build bins in double (grid_build.comp); a device without it runs every other pass.
  float64_ = HasFloat64(physical_);
  features.shaderFloat64 = float64_ ? VK_TRUE : VK_FALSE;
  const float priority = 1.0f;
  VkDeviceQueueCreateInfo qci{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
  qci.queueFamilyIndex = family_;
  qci.queueCount = 1;
  qci.pQueuePriorities = &priority;
  // 64-bit buffer atomics: intersect's closest hits and shade's fixed-point sums (both checked by
  // CheckRequirements before the device is made).
  VkPhysicalDeviceVulkan12Features want12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
  want12.shaderBufferInt64Atomics = VK_TRUE;
  VkDeviceCreateInfo dci{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
  dci.pNext = &want12;
  dci.queueCreateInfoCount = 1;
  dci.pQueueCreateInfos = &qci;
  dci.pEnabledFeatures = &features;
  RS_VK(vkCreateDevice(physical_, &dci, nullptr, &device_));
  vkGetDeviceQueue(device_, family_, 0, &queue_);
  VkCommandPoolCreateInfo pci{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
  pci.queueFamilyIndex = family_;
  pci.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
  RS_VK(vkCreateCommandPool(device_, &pci, nullptr, &command_pool_));
  pool_ = std::make_unique<MemoryPool>();
  pool_->Init(device_, max_allocations_);
  return Status::Ok();
}

Status CreateInstance(VkInstance& out, VkDebugUtilsMessengerEXT* messenger) {
  VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
  app.pApplicationName = "rayspace";
  app.apiVersion = VK_API_VERSION_1_2;
  VkInstanceCreateInfo ici{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
  ici.pApplicationInfo = &app;
  std::vector<const char*> extensions;
  std::uint32_t n = 0;
  vkEnumerateInstanceExtensionProperties(nullptr, &n, nullptr);
  std::vector<VkExtensionProperties> offered(n);
  vkEnumerateInstanceExtensionProperties(nullptr, &n, offered.data());
  for (const VkExtensionProperties& e : offered)
    if (std::strcmp(e.extensionName, VK_KHR_PORTABILITY_ENUMERATION_EXTENSION_NAME) == 0) {
      extensions.push_back(VK_KHR_PORTABILITY_ENUMERATION_EXTENSION_NAME);  // MoltenVK's devices are listed
      ici.flags |= VK_INSTANCE_CREATE_ENUMERATE_PORTABILITY_BIT_KHR;
    }
  ValidationChain chain;
  const bool validate = messenger && ValidationRequested();
  if (validate) RS_TRY(AddValidation(ici, chain, extensions));
  ici.enabledExtensionCount = static_cast<std::uint32_t>(extensions.size());
  ici.ppEnabledExtensionNames = extensions.data();
  RS_VK(vkCreateInstance(&ici, nullptr, &out));
  if (validate) RS_TRY(CreateMessenger(out, *messenger));
  return Status::Ok();
}

namespace {

// Refuses a device that lacks a requirement, naming each; and a --device-lacks name that is no
// requirement.
Status CheckDevice(VkPhysicalDevice d, int index) {
  const std::vector<Requirement> reqs = CheckRequirements(d, DeviceLacks());
  if (const std::string unknown = UnknownLack(reqs); !unknown.empty())
    return Status::Fail(fmt::format("--device-lacks '{}': not a requirement (rayspace devices lists them)", unknown));
  if (const std::string unmet = Unmet(reqs); !unmet.empty()) {
    VkPhysicalDeviceProperties p;
    vkGetPhysicalDeviceProperties(d, &p);
    return Status::Fail(fmt::format("--device {} ('{}') lacks what rayspace needs: {}", index, p.deviceName, unmet));
  }
  return Status::Ok();
}

}  // namespace

namespace {

// "0 'name', 1 'name'": what --device may name, for its error.
std::string DeviceList(const std::vector<VkPhysicalDevice>& devs) {
  std::string list;
  for (std::size_t i = 0; i < devs.size(); ++i) {
    VkPhysicalDeviceProperties p{};
    vkGetPhysicalDeviceProperties(devs[i], &p);
    list += fmt::format("{}{} '{}'", i ? ", " : "", i, p.deviceName);
  }
  return list;
}
}  // namespace

Status Context::Create(int device, std::unique_ptr<Context>& out, const sim::DeviceConfig& simulated) {
  if (device == kSimulatedDevice) return CreateSimulated(simulated, out);
  auto c = std::make_unique<Context>();
  RS_TRY(CreateInstance(c->instance_, &c->messenger_));
  std::uint32_t n = 0;
  RS_VK(vkEnumeratePhysicalDevices(c->instance_, &n, nullptr));
  if (n == 0) return Status::Fail("no Vulkan device found (install a driver, e.g. Debian's mesa-vulkan-drivers for lavapipe)");
  std::vector<VkPhysicalDevice> devs(n);
  RS_VK(vkEnumeratePhysicalDevices(c->instance_, &n, devs.data()));
  if (device >= static_cast<int>(n)) return Status::Fail(fmt::format("--device {}: only {} Vulkan device(s): {}", device, n, DeviceList(devs)));
  const int chosen = device >= 0 ? device : PreferredDevice(devs);
  c->physical_ = devs[chosen];
  RS_TRY(CheckDevice(c->physical_, chosen));
  c->ReadProperties();
  if (Status s = c->CreateDevice(); !s) return s;
  c->observer_ = CurrentSettings().observer;
  out = std::move(c);
  return Status::Ok();
}

Status Context::CreateSimulated(const sim::DeviceConfig& config, std::unique_ptr<Context>& out) {
  const std::uint32_t subgroup_size = config.subgroup_size;
  if (subgroup_size < 1 || subgroup_size > 128) return Status::Fail(fmt::format("a simulated subgroup of {} invocations (1 to 128)", subgroup_size));
  auto c = std::make_unique<Context>();
  c->simulated_ = true;
  c->sim_config_ = config;
  c->device_name_ = fmt::format("rayspace simulator (subgroup size {}", subgroup_size);
  if (config.layout.layout != sim::SubgroupLayout::kLinear) c->device_name_ += fmt::format(", {} subgroup layout", config.layout.ToString());
  if (config.arithmetic.model != sim::DeviceModel::kLavapipe) c->device_name_ += fmt::format(", {} arithmetic", config.arithmetic.ToString());
  c->device_name_ += ")";
  c->driver_ = "rayspace sim: the kernels' SPIR-V on the CPU";
  // lavapipe's limits, so that the host code splits and pages as it does there.
  c->max_storage_range_ = c->storage_limit_ = VkDeviceSize{128} << 20;
  c->float64_ = true;
  c->subgroup_features_ = ~VkSubgroupFeatureFlags{0};  // the executor's scope decides (sim/scope.h)
  c->max_stage_storage_buffers_ = 1u << 20;
  c->max_image_side_ = 16384;
  c->subgroup_size_ = subgroup_size;
  c->max_invocations_ = c->max_size_x_ = 1024;
  c->observer_ = CurrentSettings().observer;
  out = std::move(c);
  return Status::Ok();
}

Context::~Context() {
  if (device_) {
    vkDeviceWaitIdle(device_);
    pool_.reset();  // memory before the device
    vkDestroyCommandPool(device_, command_pool_, nullptr);
    vkDestroyDevice(device_, nullptr);
  }
  if (instance_) {
    // What the layer says about teardown (objects never destroyed) can fail no call: it goes to
    // stderr, and the process's exit code (ValidationFailedAtExit).
    if (ValidationPending()) ReportAtExit(TakeValidationMessages());
    DestroyMessenger(instance_, messenger_);
    vkDestroyInstance(instance_, nullptr);
  }
}

Status Context::SubmitAndWait(VkCommandBuffer cmd) {
  VkSubmitInfo si{VK_STRUCTURE_TYPE_SUBMIT_INFO};
  si.commandBufferCount = 1;
  si.pCommandBuffers = &cmd;
  VkFenceCreateInfo fci{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
  VkFence fence;
  RS_VK(vkCreateFence(device_, &fci, nullptr, &fence));
  Status st = Status::Ok();
  if (VkResult r = vkQueueSubmit(queue_, 1, &si, fence); r != VK_SUCCESS)
    st = Status::Fail("vkQueueSubmit", r);
  else if (r = vkWaitForFences(device_, 1, &fence, VK_TRUE, UINT64_MAX); r != VK_SUCCESS)
    st = Status::Fail("vkWaitForFences", r);
  vkDestroyFence(device_, fence, nullptr);
  return st;
}

Status Context::Stage(const Buffer& b, void* host, std::size_t bytes, bool to_device) {
  if (bytes == 0) return Status::Ok();
  Buffer staging;
  RS_TRY(CreateBuffer(bytes, staging, /*storage=*/false));
  if (!staging.mapped()) return Status::Fail("staging: no host-visible memory for a staging buffer");
  if (to_device) std::memcpy(staging.mapped_, host, bytes);
  Recorder rec(*this);
  RS_TRY(rec.CopyBuffer(to_device ? staging : b, to_device ? b : staging, bytes));
  RS_TRY(rec.Submit());
  if (!to_device) std::memcpy(host, staging.mapped_, bytes);
  if (ValidationPending()) return Status::Fail(fmt::format("staging copy: {}", TakeValidationMessages()));
  return Status::Ok();
}

std::size_t Context::memory_allocations() const { return pool_ ? pool_->allocations() : 0; }
std::size_t Context::peak_memory_allocations() const { return pool_ ? pool_->peak_allocations() : 0; }

std::uint32_t Context::FindMemoryType(std::uint32_t bits, VkMemoryPropertyFlags flags) const {
  for (std::uint32_t i = 0; i < memory_.memoryTypeCount; ++i)
    if ((bits & (1u << i)) && (memory_.memoryTypes[i].propertyFlags & flags) == flags) return i;
  return UINT32_MAX;
}

void Context::LimitForTesting(VkDeviceSize storage_bytes, std::uint32_t groups_x) {
  if (storage_bytes) storage_limit_ = std::min<VkDeviceSize>(storage_limit_, storage_bytes);
  if (groups_x) max_groups_[0] = std::min(max_groups_[0], groups_x);
}

namespace {
// `bytes` from p filled with copies of `word`, its low bytes first in a tail shorter than a word.
void FillWords(void* p, std::size_t bytes, std::uint32_t word) {
  auto* b = static_cast<std::uint8_t*>(p);
  const std::size_t whole = bytes / 4 * 4;
  for (std::size_t k = 0; k < whole; k += 4) std::memcpy(b + k, &word, 4);  // a fixed size: vector stores
  std::memcpy(b + whole, &word, bytes - whole);
}
}  // namespace

Status Context::CreateBuffer(std::size_t bytes, Buffer& out, bool storage, bool poison) {
  if (storage && bytes > storage_limit_)
    return Status::Fail(fmt::format("a storage buffer of {} bytes exceeds {} of '{}'", bytes,
                                    storage_limit_ == max_storage_range_
                                        ? fmt::format("maxStorageBufferRange {}", max_storage_range_)
                                        : fmt::format("the lowered binding limit {} (maxStorageBufferRange {})",
                                                      storage_limit_, max_storage_range_),
                                    device_name_));
  Buffer b;
  b.device_ = device_;
  b.size_ = bytes;
  if (simulated_) {
    const std::size_t guard = storage ? Buffer::kGuardBytes : 0;
    b.host_ = std::make_unique<std::uint8_t[]>(bytes + guard);
    b.mapped_ = b.host_.get();
    b.ctx_ = this;
    std::memset(b.mapped_, 0, bytes);
    return Finish(b, guard, poison && storage, storage, out);
  }
  // Guard words after a storage buffer, where a binding of the whole still fits the device.
  const std::size_t guard = storage && bytes + Buffer::kGuardBytes <= max_storage_range_ ? Buffer::kGuardBytes : 0;
  VkBufferCreateInfo bci{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
  bci.size = std::max<std::size_t>(bytes + guard, 16);
  bci.usage = (storage ? VK_BUFFER_USAGE_STORAGE_BUFFER_BIT : 0) | VK_BUFFER_USAGE_TRANSFER_DST_BIT |
              VK_BUFFER_USAGE_TRANSFER_SRC_BIT;
  RS_VK(vkCreateBuffer(device_, &bci, nullptr, &b.buffer_));
  VkMemoryRequirements req;
  vkGetBufferMemoryRequirements(device_, b.buffer_, &req);
  // Storage buffers: device-local memory the host can map (a GPU's resizable BAR, an integrated
  // GPU's or lavapipe's memory), else any the host can map. Read-back targets: host-cached, which
  // a GPU writes and the host reads fast.
  // A discrete GPU without resizable BAR (or --device-lacks mappableDeviceLocal) has no such memory:
  // its storage buffers are device-local and staged.
  constexpr VkMemoryPropertyFlags kMappable = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
  const bool map_local = !DeviceLacks().count("mappableDeviceLocal");
  std::uint32_t type = UINT32_MAX;
  bool mappable = true;
  if (storage) {
    if (map_local) type = FindMemoryType(req.memoryTypeBits, kMappable | VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
    if (type == UINT32_MAX) {
      type = FindMemoryType(req.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
      mappable = false;
    }
  } else {
    type = FindMemoryType(req.memoryTypeBits, kMappable | VK_MEMORY_PROPERTY_HOST_CACHED_BIT);
  }
  if (type == UINT32_MAX) {
    type = FindMemoryType(req.memoryTypeBits, kMappable);
    mappable = true;
  }
  if (type == UINT32_MAX) return Status::Fail("no memory type for a buffer");
  b.ctx_ = this;
  b.pool_ = pool_.get();
  RS_TRY(pool_->Allocate(req, type, mappable, /*image=*/false, b.range_));
  RS_VK(vkBindBufferMemory(device_, b.buffer_, b.range_.memory, b.range_.offset));
  b.mapped_ = b.range_.mapped;
  // Staged memory is neither poisoned nor guarded: the host cannot watch it.
  return Finish(b, b.mapped_ ? guard : 0, poison && storage && b.mapped_, storage, out);
}

Status Context::Finish(Buffer& b, std::size_t guard, bool poison, bool storage, Buffer& out) {
  if (poison && CurrentSettings().poison_new_buffers) FillWords(b.mapped_, b.size_, Buffer::kPoisonWord);
  if (guard) {
    b.guard_ = guard;
    FillWords(static_cast<std::uint8_t*>(b.mapped_) + b.size_, guard, Buffer::kGuardWord);
  }
  b.observed_ = storage && observer_;
  out = std::move(b);
  if (out.observed_) observer_->BufferCreated(out);
  return Status::Ok();
}

static_assert(Buffer::kPoisonWord == layout::kPoisonWord, "the host's poison is the contract's");

bool Context::StrictMath() { return CurrentSettings().strict_math; }

Status Context::CreateKernel(const std::string& name, std::span<const std::uint32_t> spirv, std::uint32_t bindings,
                             std::uint32_t fault, Kernel& k, std::uint32_t local_size) {
  // Paged arrays (paged.glsl) take several bindings each; a device with fewer is refused by name.
  if (bindings > max_stage_storage_buffers_)
    return Status::Fail(fmt::format("kernel {} needs {} storage-buffer bindings; '{}' allows {} (maxPerStageDescriptorStorageBuffers)",
                                    name, bindings, device_name_, max_stage_storage_buffers_));
  if (local_size > max_invocations_ || local_size > max_size_x_)
    return Status::Fail(fmt::format("--local-size {}: '{}' allows at most {} invocations per workgroup "
                                    "(maxComputeWorkGroupInvocations {}, maxComputeWorkGroupSize[0] {})",
                                    local_size, device_name_, std::min(max_invocations_, max_size_x_), max_invocations_, max_size_x_));
  k.refusal_.clear();
  if (const VkSubgroupFeatureFlags missing = SubgroupFeaturesOf(spirv) & ~subgroup_features_; missing != 0) {
    std::string names;
    for (VkSubgroupFeatureFlags bit = 1; bit != 0 && bit <= missing; bit <<= 1)
      if (missing & bit) names += (names.empty() ? "" : ", ") + SubgroupFeatureName(bit);
    k.refusal_ = fmt::format("kernel {} declares subgroup operations '{}' lacks in compute: {} (rayspace devices)", name,
                             device_name_, names);
  }
  k.device_ = device_;
  k.local_size_ = local_size;
  k.name_ = name;
  k.bindings_ = bindings;
  k.spirv_.assign(spirv.begin(), spirv.end());
  if (!simulated_) {
    if (Status st = CreateLayouts(device_, bindings, VK_SHADER_STAGE_COMPUTE_BIT, 128, k.set_layout_, k.layout_); !st)
      return st;
  }
  // common.glsl: kFault, kLocalSize, kStrictMath (a VkBool32).
  k.spec_[0] = fault;
  k.spec_[1] = k.local_size_;
  k.spec_[2] = StrictMath() ? VK_TRUE : VK_FALSE;
  if (observer_) observer_->KernelCreated(k, spirv, k.spec_);
  return Status::Ok();
}

// common.glsl's specialization constants as spirv-opt reads them (SpecId -> text).
static std::map<std::uint32_t, std::string> SpecText(const std::uint32_t spec[3]) {
  return {{0, std::to_string(spec[0])}, {1, std::to_string(spec[1])}, {2, spec[2] ? "true" : "false"}};
}

// --strict-math's promise holds only for a kernel whose strict pipeline has no division or root
// left that a device may round loosely (the grids' build, in double, has); checked once per kernel
// on the pipeline as it would run (gpu/tests/strict_spirv_test.cpp holds every built-in kernel to it).
Status StrictMathRefusal(const Kernel& k, std::span<const std::uint32_t> spirv, const std::uint32_t spec[3]) {
  std::vector<std::string> loose;
  try {
    loose = sim::LooselyRounded(sim::Specialized(spirv, SpecText(spec), k.name()));
  } catch (const std::exception& e) {
    return Status::Fail(fmt::format("kernel {}: {}", k.name(), e.what()));
  }
  if (loose.empty()) return Status::Ok();
  return Status::Refuse(fmt::format("--strict-math: kernel {} still divides or takes roots as the device rounds them ({}{}); "
                                    "it has no exact path, so its bits are not promised (run it without --strict-math)",
                                    k.name(), loose.front(), loose.size() > 1 ? fmt::format(" and {} more", loose.size() - 1) : ""));
}

Status Context::CreatePipeline(const Kernel& k) const {
  if (!k.refusal_.empty()) return Status::Refuse(k.refusal_);
  if (k.spec_[2] && !k.strict_checked_) {
    RS_TRY(StrictMathRefusal(k, k.spirv_, k.spec_));
    k.strict_checked_ = true;
  }
  if (simulated_) {
    if (k.program_) return Status::Ok();
    try {
      k.program_ = std::make_shared<const sim::Program>(sim::Prepare(
          k.spirv_, {{0, std::to_string(k.spec_[0])}, {1, std::to_string(k.spec_[1])}, {2, std::to_string(k.spec_[2])}}, k.name_));
    } catch (const std::exception& e) {
      return Status::Fail(fmt::format("kernel {} on the simulated device: {}", k.name_, e.what()));
    }
    return Status::Ok();
  }
  if (k.pipeline_ != VK_NULL_HANDLE) return Status::Ok();
  // The device gets the module with these constants frozen and the branches they decide removed
  // (sim::WithBranchesDecided): lavapipe inlines every call before it drops dead code, so the
  // strict-math path, dead unless --strict-math, would be copied into every Div and Sqrt call site.
  std::vector<std::uint32_t> decided;
  try {
    decided = sim::WithBranchesDecided(k.spirv_, SpecText(k.spec_), k.name_);
  } catch (const std::exception& e) {
    return Status::Fail(fmt::format("kernel {}: {}", k.name_, e.what()));
  }
  vkDestroyShaderModule(device_, k.module_, nullptr);
  k.module_ = VK_NULL_HANDLE;
  // The float controls the device offers, requested (rayspace/gpu/float_controls.h).
  RS_TRY(CreateModule(device_, WithFloatControls(decided, float_controls_), k.module_));
  // The constants are frozen in the module already; they are still given, as the pipeline's
  // record of what it was made with (the layer and a capture tool show them).
  const VkSpecializationMapEntry entries[3] = {{0, 0, 4}, {1, 4, 4}, {2, 8, 4}};
  VkSpecializationInfo si{3, entries, sizeof k.spec_, k.spec_};
  VkComputePipelineCreateInfo cp{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
  cp.stage = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO};
  cp.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
  cp.stage.module = k.module_;
  cp.stage.pName = "main";
  cp.stage.pSpecializationInfo = &si;
  cp.layout = k.layout_;
  RS_VK(vkCreateComputePipelines(device_, VK_NULL_HANDLE, 1, &cp, nullptr, &k.pipeline_));
  return Status::Ok();
}

Status Context::SetKernelFault(Kernel& k, std::uint32_t fault) const {
  if (k.spec_[0] == fault) return Status::Ok();
  if (observer_) return Status::Fail(fmt::format("kernel {}: its planted fault cannot change while an observer records it", k.name_));
  k.program_.reset();
  if (!simulated_) vkDestroyPipeline(device_, k.pipeline_, nullptr);
  k.pipeline_ = VK_NULL_HANDLE;
  k.strict_checked_ = false;
  k.spec_[0] = fault;
  return Status::Ok();
}

Status Context::CreateImage(VkFormat format, VkImageUsageFlags usage, VkImageAspectFlags aspect, std::uint32_t width,
                            std::uint32_t height, Image& out) {
  if (simulated_) return Status::Fail("the simulated device runs compute kernels only (the raster comes from the emulator)");
  if (width < 1 || height < 1 || width > max_image_side_ || height > max_image_side_)
    return Status::Fail(fmt::format("a {} x {} image is outside [1, {}] (maxImageDimension2D of '{}')", width, height,
                                    max_image_side_, device_name_));
  Image im;
  im.device_ = device_;
  im.aspect_ = aspect;
  im.width_ = width;
  im.height_ = height;
  VkImageCreateInfo ici{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
  ici.imageType = VK_IMAGE_TYPE_2D;
  ici.format = format;
  ici.extent = {width, height, 1};
  ici.mipLevels = 1;
  ici.arrayLayers = 1;
  ici.samples = VK_SAMPLE_COUNT_1_BIT;
  ici.tiling = VK_IMAGE_TILING_OPTIMAL;
  ici.usage = usage | VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
  RS_VK(vkCreateImage(device_, &ici, nullptr, &im.image_));
  VkMemoryRequirements req;
  vkGetImageMemoryRequirements(device_, im.image_, &req);
  std::uint32_t type = FindMemoryType(req.memoryTypeBits, VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);
  if (type == UINT32_MAX) type = FindMemoryType(req.memoryTypeBits, 0);
  if (type == UINT32_MAX) return Status::Fail(fmt::format("no memory type for a {} x {} image on '{}'", width, height, device_name_));
  im.pool_ = pool_.get();
  RS_TRY(pool_->Allocate(req, type, /*host_visible=*/false, /*image=*/true, im.range_));
  RS_VK(vkBindImageMemory(device_, im.image_, im.range_.memory, im.range_.offset));
  VkImageViewCreateInfo vci{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
  vci.image = im.image_;
  vci.viewType = VK_IMAGE_VIEW_TYPE_2D;
  vci.format = format;
  vci.subresourceRange = {aspect, 0, 1, 0, 1};
  RS_VK(vkCreateImageView(device_, &vci, nullptr, &im.view_));
  out = std::move(im);
  return Status::Ok();
}

namespace {

// One subpass writing every colour attachment and the depth attachment; each attachment is cleared
// on load and ends in TRANSFER_SRC_OPTIMAL for the read-back copy.
Status CreateRenderPass(VkDevice device, const GraphicsDesc& d, VkRenderPass& out) {
  const std::uint32_t colors = static_cast<std::uint32_t>(d.colors.size());
  std::vector<VkAttachmentDescription> att(colors + 1);
  std::vector<VkAttachmentReference> color_ref(colors);
  for (std::uint32_t i = 0; i <= colors; ++i) {
    att[i].format = i < colors ? d.colors[i] : d.depth;
    att[i].samples = VK_SAMPLE_COUNT_1_BIT;
    att[i].loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
    att[i].storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    att[i].stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
    att[i].stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
    att[i].initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    att[i].finalLayout = VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL;
    if (i < colors) color_ref[i] = {i, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL};
  }
  VkAttachmentReference depth_ref{colors, VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL};
  VkSubpassDescription sub{};
  sub.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
  sub.colorAttachmentCount = colors;
  sub.pColorAttachments = color_ref.data();
  sub.pDepthStencilAttachment = &depth_ref;
  // Before: the previous draw's copies out of these images finish before the clears (write after
  // read). After: the attachment writes and the final layout transition finish before the copies
  // read the images (read after write); neither is implied by the end of a render pass.
  constexpr VkPipelineStageFlags kAttachmentStages = VK_PIPELINE_STAGE_COLOR_ATTACHMENT_OUTPUT_BIT |
                                                     VK_PIPELINE_STAGE_EARLY_FRAGMENT_TESTS_BIT |
                                                     VK_PIPELINE_STAGE_LATE_FRAGMENT_TESTS_BIT;
  constexpr VkAccessFlags kAttachmentWrites = VK_ACCESS_COLOR_ATTACHMENT_WRITE_BIT | VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_WRITE_BIT |
                                              VK_ACCESS_DEPTH_STENCIL_ATTACHMENT_READ_BIT;
  VkSubpassDependency deps[2] = {};
  deps[0].srcSubpass = VK_SUBPASS_EXTERNAL;
  deps[0].dstSubpass = 0;
  deps[0].srcStageMask = VK_PIPELINE_STAGE_TRANSFER_BIT;
  deps[0].dstStageMask = kAttachmentStages;
  deps[0].srcAccessMask = 0;
  deps[0].dstAccessMask = kAttachmentWrites;
  deps[1].srcSubpass = 0;
  deps[1].dstSubpass = VK_SUBPASS_EXTERNAL;
  deps[1].srcStageMask = kAttachmentStages;
  deps[1].dstStageMask = VK_PIPELINE_STAGE_TRANSFER_BIT;
  deps[1].srcAccessMask = kAttachmentWrites;
  deps[1].dstAccessMask = VK_ACCESS_TRANSFER_READ_BIT;
  VkRenderPassCreateInfo rpci{VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO};
  rpci.attachmentCount = colors + 1;
  rpci.pAttachments = att.data();
  rpci.subpassCount = 1;
  rpci.pSubpasses = &sub;
  rpci.dependencyCount = d.drop_dependencies_for_testing ? 0 : 2;
  rpci.pDependencies = deps;
  RS_VK(vkCreateRenderPass(device, &rpci, nullptr, &out));
  return Status::Ok();
}

// The fixed-function state of GraphicsDesc: triangle lists, no culling, LESS depth test with writes.
Status CreateGraphicsPipeline(VkDevice device, const GraphicsDesc& d, VkShaderModule vert, VkShaderModule frag,
                              VkPipelineLayout layout, VkRenderPass pass, VkPipeline& out) {
  VkPipelineShaderStageCreateInfo stages[2] = {{VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO},
                                               {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO}};
  stages[0].stage = VK_SHADER_STAGE_VERTEX_BIT;
  stages[0].module = vert;
  stages[0].pName = "main";
  stages[1].stage = VK_SHADER_STAGE_FRAGMENT_BIT;
  stages[1].module = frag;
  stages[1].pName = "main";
  // kFault (constant 0) and kStrictMath (constant 2, a VkBool32), as for compute kernels.
  const std::uint32_t spec[2] = {d.fault, Context::StrictMath() ? VK_TRUE : VK_FALSE};
  const VkSpecializationMapEntry entries[2] = {{0, 0, 4}, {2, 4, 4}};
  const VkSpecializationInfo spec_info{2, entries, sizeof spec, spec};
  stages[0].pSpecializationInfo = &spec_info;
  stages[1].pSpecializationInfo = &spec_info;
  VkPipelineVertexInputStateCreateInfo vi{VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO};
  VkPipelineInputAssemblyStateCreateInfo ia{VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO};
  ia.topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST;
  VkViewport viewport{0.0f, 0.0f, static_cast<float>(d.width), static_cast<float>(d.height), 0.0f, 1.0f};
  VkRect2D scissor{{0, 0}, {d.width, d.height}};
  VkPipelineViewportStateCreateInfo vp{VK_STRUCTURE_TYPE_PIPELINE_VIEWPORT_STATE_CREATE_INFO};
  vp.viewportCount = 1;
  vp.pViewports = &viewport;
  vp.scissorCount = 1;
  vp.pScissors = &scissor;
  VkPipelineRasterizationStateCreateInfo rs{VK_STRUCTURE_TYPE_PIPELINE_RASTERIZATION_STATE_CREATE_INFO};
  rs.polygonMode = VK_POLYGON_MODE_FILL;
  rs.cullMode = VK_CULL_MODE_NONE;
  rs.frontFace = VK_FRONT_FACE_COUNTER_CLOCKWISE;
  rs.lineWidth = 1.0f;
  VkPipelineMultisampleStateCreateInfo ms{VK_STRUCTURE_TYPE_PIPELINE_MULTISAMPLE_STATE_CREATE_INFO};
  ms.rasterizationSamples = VK_SAMPLE_COUNT_1_BIT;
  VkPipelineDepthStencilStateCreateInfo ds{VK_STRUCTURE_TYPE_PIPELINE_DEPTH_STENCIL_STATE_CREATE_INFO};
  ds.depthTestEnable = VK_TRUE;
  ds.depthWriteEnable = VK_TRUE;
  ds.depthCompareOp = VK_COMPARE_OP_LESS;
  // One blend state for every attachment (differing states need the independentBlend feature);
  // writing components a format lacks is ignored, so RGBA suits the single-channel targets too.
  VkPipelineColorBlendAttachmentState all{};
  all.colorWriteMask = VK_COLOR_COMPONENT_R_BIT | VK_COLOR_COMPONENT_G_BIT | VK_COLOR_COMPONENT_B_BIT | VK_COLOR_COMPONENT_A_BIT;
  std::vector<VkPipelineColorBlendAttachmentState> cba(d.colors.size(), all);
  if (d.differing_blend_for_testing) cba.back().colorWriteMask = VK_COLOR_COMPONENT_R_BIT;
  VkPipelineColorBlendStateCreateInfo cb{VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO};
  cb.attachmentCount = static_cast<std::uint32_t>(cba.size());
  cb.pAttachments = cba.data();
  VkGraphicsPipelineCreateInfo gp{VK_STRUCTURE_TYPE_GRAPHICS_PIPELINE_CREATE_INFO};
  gp.stageCount = 2;
  gp.pStages = stages;
  gp.pVertexInputState = &vi;
  gp.pInputAssemblyState = &ia;
  gp.pViewportState = &vp;
  gp.pRasterizationState = &rs;
  gp.pMultisampleState = &ms;
  gp.pDepthStencilState = &ds;
  gp.pColorBlendState = &cb;
  gp.layout = layout;
  gp.renderPass = pass;
  RS_VK(vkCreateGraphicsPipelines(device, VK_NULL_HANDLE, 1, &gp, nullptr, &out));
  return Status::Ok();
}

}  // namespace

Status Context::CreateGraphics(const GraphicsDesc& d, std::span<const Image* const> attachments, Graphics& g) {
  if (simulated_) return Status::Fail("the simulated device runs compute kernels only (the raster comes from the emulator)");
  if (attachments.size() != d.colors.size() + 1)
    return Status::Fail(fmt::format("graphics {}: {} colour formats and {} attachments (colours + depth)", d.name,
                                    d.colors.size(), attachments.size()));
  g.device_ = device_;
  g.name_ = d.name;
  g.bindings_ = d.bindings;
  g.attachments_ = static_cast<std::uint32_t>(attachments.size());
  g.width_ = d.width;
  g.height_ = d.height;
  if (Status st = CreateModule(device_, d.vert_spirv, g.vert_); !st) return st;
  if (Status st = CreateModule(device_, d.frag_spirv, g.frag_); !st) return st;
  if (Status st = CreateLayouts(device_, d.bindings, VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, 0,
                                g.set_layout_, g.layout_);
      !st)
    return st;
  if (Status st = CreateRenderPass(device_, d, g.pass_); !st) return st;
  std::vector<VkImageView> views(attachments.size());
  for (std::size_t i = 0; i < views.size(); ++i) views[i] = attachments[i]->view();
  VkFramebufferCreateInfo fci{VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO};
  fci.renderPass = g.pass_;
  fci.attachmentCount = g.attachments_;
  fci.pAttachments = views.data();
  fci.width = d.width;
  fci.height = d.height;
  fci.layers = 1;
  RS_VK(vkCreateFramebuffer(device_, &fci, nullptr, &g.framebuffer_));
  return CreateGraphicsPipeline(device_, d, g.vert_, g.frag_, g.layout_, g.pass_, g.pipeline_);
}

Recorder::~Recorder() {
  for (VkDescriptorPool p : pools_) vkDestroyDescriptorPool(ctx_.device_, p, nullptr);
  if (cmd_) vkFreeCommandBuffers(ctx_.device_, ctx_.command_pool_, 1, &cmd_);
}

Status Recorder::Begin() {
  if (!cmd_) {
    VkCommandBufferAllocateInfo ai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    ai.commandPool = ctx_.command_pool_;
    ai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    ai.commandBufferCount = 1;
    RS_VK(vkAllocateCommandBuffers(ctx_.device_, &ai, &cmd_));
  }
  VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  RS_VK(vkBeginCommandBuffer(cmd_, &bi));
  recording_ = true;
  return Status::Ok();
}

Status Recorder::BindSet(const char* kind, const std::string& name, VkDescriptorSetLayout layout,
                         std::span<const Buffer* const> buffers, VkDescriptorSet& set) {
  const auto bindings = static_cast<std::uint32_t>(buffers.size());
  // A pass may record any number of parts before its submit: when the current descriptor pool has
  // no room for this set, the next one is used (and created once); all are reset after the submit.
  if (bindings > kPoolDescriptors) return Status::Fail(fmt::format("{} {}: {} bindings exceed a descriptor pool", kind, name, bindings));
  if (sets_left_ == 0 || descriptors_left_ < bindings) {
    if (++current_ >= pools_.size()) {
      VkDescriptorPoolSize ps{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, kPoolDescriptors};
      VkDescriptorPoolCreateInfo dp{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
      dp.maxSets = kPoolSets;
      dp.poolSizeCount = 1;
      dp.pPoolSizes = &ps;
      VkDescriptorPool pool;
      RS_VK(vkCreateDescriptorPool(ctx_.device_, &dp, nullptr, &pool));
      pools_.push_back(pool);
      ++ctx_.descriptor_pools_;
    }
    sets_left_ = kPoolSets;
    descriptors_left_ = kPoolDescriptors;
  }
  --sets_left_;
  descriptors_left_ -= bindings;
  VkDescriptorSetAllocateInfo ai{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
  ai.descriptorPool = pools_[current_];
  ai.descriptorSetCount = 1;
  ai.pSetLayouts = &layout;
  RS_VK(vkAllocateDescriptorSets(ctx_.device_, &ai, &set));
  std::vector<VkDescriptorBufferInfo> infos(buffers.size());
  std::vector<VkWriteDescriptorSet> writes(buffers.size());
  for (std::size_t i = 0; i < buffers.size(); ++i) {
    infos[i] = {buffers[i]->handle(), 0, VK_WHOLE_SIZE};
    writes[i] = {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
    writes[i].dstSet = set;
    writes[i].dstBinding = static_cast<std::uint32_t>(i);
    writes[i].descriptorCount = 1;
    writes[i].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    writes[i].pBufferInfo = &infos[i];
  }
  vkUpdateDescriptorSets(ctx_.device_, static_cast<std::uint32_t>(writes.size()), writes.data(), 0, nullptr);
  return Status::Ok();
}

Status Recorder::Dispatch(const Kernel& k, std::span<const Buffer* const> buffers, const void* push,
                          std::size_t push_size, std::uint32_t invocations) {
  return DispatchGroups(k, buffers, push, push_size, (std::uint64_t{invocations} + k.local_size_ - 1) / k.local_size_);
}

Status Recorder::DispatchGroups(const Kernel& k, std::span<const Buffer* const> buffers, const void* push,
                                std::size_t push_size, std::uint64_t groups) {
  if (!recording_ && !ctx_.simulated_) {
    Status s = Begin();
    if (!s) return s;
  }
  recording_ = true;
  if (buffers.size() != k.bindings_) return Status::Fail(fmt::format("kernel {} takes {} buffers, got {}", k.name_, k.bindings_, buffers.size()));
  if (Status st = ctx_.CreatePipeline(k); !st) return st;
  bound_.emplace_back(k.name_, std::vector<const Buffer*>(buffers.begin(), buffers.end()));
  // Launches wider than maxComputeWorkGroupCount[0] groups fold into rows of groups; kernels index
  // with GlobalIndex() (common.glsl), which reads the grid row-major, and skip indices past the end.
  const std::uint32_t gx = static_cast<std::uint32_t>(std::min<std::uint64_t>(groups, ctx_.max_groups_[0]));
  const std::uint64_t gy = gx ? (groups + gx - 1) / gx : 0;
  if (gy > ctx_.max_groups_[1])
    return Status::Fail(fmt::format("kernel {}: {} invocations need {} x {} workgroups, beyond maxComputeWorkGroupCount",
                                    k.name_, groups * k.local_size_, gx, gy));
  if (gy > 1) ++ctx_.folded_launches_;
  if (ctx_.simulated_) {
    SimStep step;
    step.kernel = &k;
    step.buffers.assign(buffers.begin(), buffers.end());
    if (push && push_size) step.push.assign(static_cast<const std::uint8_t*>(push), static_cast<const std::uint8_t*>(push) + push_size);
    step.gx = gx;
    step.gy = static_cast<std::uint32_t>(gy);
    if (groups > 0) {
      sim_steps_.push_back(std::move(step));
      ++k.launches_;
    }
    dispatched_ = true;
    if (ctx_.observer_)
      ctx_.observer_->Dispatched(*this, k, buffers, {static_cast<const std::uint8_t*>(push), push ? push_size : 0}, gx,
                                 static_cast<std::uint32_t>(gy));
    return Status::Ok();
  }
  VkDescriptorSet set;
  if (Status st = BindSet("kernel", k.name_, k.set_layout_, buffers, set); !st) return st;
  vkCmdBindPipeline(cmd_, VK_PIPELINE_BIND_POINT_COMPUTE, k.pipeline_);
  vkCmdBindDescriptorSets(cmd_, VK_PIPELINE_BIND_POINT_COMPUTE, k.layout_, 0, 1, &set, 0, nullptr);
  if (push_size) vkCmdPushConstants(cmd_, k.layout_, VK_SHADER_STAGE_COMPUTE_BIT, 0, static_cast<std::uint32_t>(push_size), push);
  if (groups > 0) {
    vkCmdDispatch(cmd_, gx, static_cast<std::uint32_t>(gy), 1);
    ++k.launches_;
  }
  dispatched_ = true;
  if (ctx_.observer_)
    ctx_.observer_->Dispatched(*this, k, buffers, {static_cast<const std::uint8_t*>(push), push ? push_size : 0}, gx,
                               static_cast<std::uint32_t>(gy));
  VkMemoryBarrier mb{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
  mb.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT;
  mb.dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_HOST_READ_BIT |
                    VK_ACCESS_TRANSFER_READ_BIT;  // a staged read-back in a later submit
  vkCmdPipelineBarrier(cmd_, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                       VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_HOST_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT, 0,
                       1, &mb, 0, nullptr, 0, nullptr);
  return Status::Ok();
}

Status Recorder::Draw(const Graphics& g, std::span<const Buffer* const> buffers, std::span<const VkClearValue> clears,
                      std::uint32_t vertices) {
  if (buffers.size() != g.bindings_ || clears.size() != g.attachments_)
    return Status::Fail(fmt::format("graphics {} takes {} buffers and {} clear values, got {} and {}", g.name_,
                                    g.bindings_, g.attachments_, buffers.size(), clears.size()));
  if (!recording_) {
    Status s = Begin();
    if (!s) return s;
  }
  VkDescriptorSet set;
  if (Status st = BindSet("graphics", g.name_, g.set_layout_, buffers, set); !st) return st;
  VkRenderPassBeginInfo rbi{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
  rbi.renderPass = g.pass_;
  rbi.framebuffer = g.framebuffer_;
  rbi.renderArea = {{0, 0}, {g.width_, g.height_}};
  rbi.clearValueCount = g.attachments_;
  rbi.pClearValues = clears.data();
  vkCmdBeginRenderPass(cmd_, &rbi, VK_SUBPASS_CONTENTS_INLINE);
  vkCmdBindPipeline(cmd_, VK_PIPELINE_BIND_POINT_GRAPHICS, g.pipeline_);
  vkCmdBindDescriptorSets(cmd_, VK_PIPELINE_BIND_POINT_GRAPHICS, g.layout_, 0, 1, &set, 0, nullptr);
  vkCmdDraw(cmd_, vertices, 1, 0, 0);
  vkCmdEndRenderPass(cmd_);
  return Status::Ok();
}

Status Recorder::CopyToHost(const Image& image, const Buffer& dst) {
  if (!recording_) {
    Status s = Begin();
    if (!s) return s;
  }
  VkBufferImageCopy copy{};
  copy.imageSubresource = {image.aspect_, 0, 0, 1};
  copy.imageExtent = {image.width_, image.height_, 1};
  vkCmdCopyImageToBuffer(cmd_, image.image_, VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, dst.handle(), 1, &copy);
  VkMemoryBarrier mb{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
  mb.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
  mb.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
  vkCmdPipelineBarrier(cmd_, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &mb, 0, nullptr, 0, nullptr);
  return Status::Ok();
}

Status Recorder::CopyBuffer(const Buffer& src, const Buffer& dst, std::size_t bytes) {
  if (ctx_.simulated_) {
    recording_ = true;
    SimStep step;
    step.src = &src;
    step.dst = &dst;
    step.bytes = bytes;
    sim_steps_.push_back(std::move(step));
    return Status::Ok();
  }
  if (!recording_) RS_TRY(Begin());
  // Before: whatever earlier commands and submits did with either buffer. After: the copy before
  // later commands (an upload) and before the host reads (a read-back).
  VkMemoryBarrier before{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
  before.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT | VK_ACCESS_HOST_WRITE_BIT;
  before.dstAccessMask = VK_ACCESS_TRANSFER_READ_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
  vkCmdPipelineBarrier(cmd_, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT | VK_PIPELINE_STAGE_HOST_BIT, VK_PIPELINE_STAGE_TRANSFER_BIT, 0, 1,
                       &before, 0, nullptr, 0, nullptr);
  const VkBufferCopy region{0, 0, bytes};
  vkCmdCopyBuffer(cmd_, src.handle(), dst.handle(), 1, &region);
  VkMemoryBarrier after{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
  after.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
  after.dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_READ_BIT |
                        VK_ACCESS_TRANSFER_WRITE_BIT | VK_ACCESS_HOST_READ_BIT;
  vkCmdPipelineBarrier(cmd_, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT | VK_PIPELINE_STAGE_HOST_BIT, 0, 1,
                       &after, 0, nullptr, 0, nullptr);
  return Status::Ok();
}

Status Recorder::SubmitSimulated() {
  const std::vector<SimStep> steps = std::move(sim_steps_);
  sim_steps_.clear();
  for (const SimStep& step : steps) {
    if (!step.kernel) {
      if (step.bytes > step.src->size() || step.bytes > step.dst->size()) return Status::Fail("a copy beyond a buffer's end");
      std::memmove(step.dst->mapped_, step.src->mapped_, step.bytes);
      continue;
    }
    sim::Dispatch d;
    d.groups[0] = step.gx;
    d.groups[1] = step.gy;
    d.subgroup_size = ctx_.subgroup_size_;
    d.schedule = ctx_.sim_config_.schedule;
    d.step_limit = ctx_.sim_config_.step_limit;
    d.checks = ctx_.sim_config_.checks;
    d.arithmetic = ctx_.sim_config_.arithmetic;
    d.layout = ctx_.sim_config_.layout;
    std::vector<std::uint8_t>& coverage = step.kernel->coverage_;
    if (coverage.size() != step.kernel->program_->code.size()) coverage.assign(step.kernel->program_->code.size(), 0);
    d.coverage = coverage.data();
    d.dispatch_index = ctx_.sim_dispatches_++;
    d.push = step.push;
    for (const Buffer* b : step.buffers) d.bindings.push_back({static_cast<std::uint8_t*>(b->mapped_), b->size_ + b->guard_, b->size_});
    sim::ExecStats stats;
    try {
      sim::Run(*step.kernel->program_, d, stats);
    } catch (const sim::SimError& e) {
      Status st = Status::Fail(fmt::format("kernel {} faulted on the simulated device: {}", step.kernel->name_, e.what()));
      if (e.checker()) {
        st.checker = sim::CheckerName(*e.checker());
        st.finding = e.what();
      } else {
        st.device_fault = true;
      }
      return st;
    }
    ctx_.sim_instructions_ += stats.lane_instructions;
  }
  return Status::Ok();
}

Status Recorder::Submit() {
  if (!recording_) return Status::Ok();
  if (ctx_.simulated_) {
    recording_ = false;
    RS_TRY(SubmitSimulated());
  } else {
    RS_VK(vkEndCommandBuffer(cmd_));
    recording_ = false;
    if (Status st = ctx_.SubmitAndWait(cmd_); !st) return st;
  }
  if (ctx_.observer_ && dispatched_) ctx_.observer_->Submitted(*this);
  const std::vector<std::pair<std::string, std::vector<const Buffer*>>> bound = std::move(bound_);
  bound_.clear();
  for (const auto& [kernel, buffers] : bound)
    for (std::size_t i = 0; i < buffers.size(); ++i) {
      std::size_t word = 0;
      std::uint32_t value = 0;
      if (buffers[i]->GuardChanged(word, value))
        return Status::Fail(fmt::format("kernel {} wrote past the end of binding {} ({} bytes): guard word {} after it is 0x{:08x}",
                                        kernel, i, buffers[i]->size(), word, value));
    }
  dispatched_ = false;
  if (ctx_.simulated_) return Status::Ok();
  for (VkDescriptorPool p : pools_) RS_VK(vkResetDescriptorPool(ctx_.device_, p, 0));
  current_ = static_cast<std::size_t>(-1);
  sets_left_ = descriptors_left_ = 0;
  RS_VK(vkResetCommandBuffer(cmd_, 0));
  return Status::Ok();
}

}  // namespace rayspace::vk
