#include "rayspace/gpu/vulkan.h"

#include <fmt/format.h>

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

#define RS_VK(call)                                             \
  do {                                                          \
    const VkResult rs_r = (call);                               \
    if (rs_r != VK_SUCCESS) return Status::Fail(#call, rs_r);   \
  } while (0)

}  // namespace

Status Status::Fail(const std::string& call, VkResult r) {
  std::string name = call.substr(0, call.find('('));
  std::string message = fmt::format("{} failed: {} ({})", name, ResultName(r), static_cast<int>(r));
  return {false, r, std::move(name), std::move(message)};
}

Buffer& Buffer::operator=(Buffer&& o) noexcept {
  std::swap(device_, o.device_);
  std::swap(buffer_, o.buffer_);
  std::swap(memory_, o.memory_);
  std::swap(size_, o.size_);
  std::swap(mapped_, o.mapped_);
  return *this;
}

Buffer::~Buffer() {
  if (!device_) return;
  if (mapped_) vkUnmapMemory(device_, memory_);
  vkDestroyBuffer(device_, buffer_, nullptr);
  vkFreeMemory(device_, memory_, nullptr);
}

Kernel::~Kernel() {
  if (!device_) return;
  vkDestroyPipeline(device_, pipeline_, nullptr);
  vkDestroyPipelineLayout(device_, layout_, nullptr);
  vkDestroyDescriptorSetLayout(device_, set_layout_, nullptr);
  vkDestroyShaderModule(device_, module_, nullptr);
}

std::vector<std::string> Context::ListDevices() {
  std::vector<std::string> out;
  VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
  app.apiVersion = VK_API_VERSION_1_2;
  VkInstanceCreateInfo ici{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
  ici.pApplicationInfo = &app;
  VkInstance inst;
  if (vkCreateInstance(&ici, nullptr, &inst) != VK_SUCCESS) return out;
  std::uint32_t n = 0;
  vkEnumeratePhysicalDevices(inst, &n, nullptr);
  std::vector<VkPhysicalDevice> devs(n);
  vkEnumeratePhysicalDevices(inst, &n, devs.data());
  for (auto d : devs) {
    VkPhysicalDeviceProperties p;
    vkGetPhysicalDeviceProperties(d, &p);
    out.push_back(p.deviceName);
  }
  vkDestroyInstance(inst, nullptr);
  return out;
}

Status Context::Create(int device, std::unique_ptr<Context>& out) {
  auto c = std::make_unique<Context>();
  VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
  app.pApplicationName = "rayspace";
  app.apiVersion = VK_API_VERSION_1_2;
  VkInstanceCreateInfo ici{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
  ici.pApplicationInfo = &app;
  RS_VK(vkCreateInstance(&ici, nullptr, &c->instance_));
  std::uint32_t n = 0;
  RS_VK(vkEnumeratePhysicalDevices(c->instance_, &n, nullptr));
  if (n == 0) return Status::Fail("no Vulkan device found (install a driver, e.g. Debian's mesa-vulkan-drivers for lavapipe)");
  std::vector<VkPhysicalDevice> devs(n);
  RS_VK(vkEnumeratePhysicalDevices(c->instance_, &n, devs.data()));
  int chosen = -1;
  if (device >= 0) {
    if (device >= static_cast<int>(n)) return Status::Fail(fmt::format("--device {}: only {} Vulkan device(s)", device, n));
    chosen = device;
  } else {
    for (std::uint32_t i = 0; i < n && chosen < 0; ++i) {
      VkPhysicalDeviceProperties p;
      vkGetPhysicalDeviceProperties(devs[i], &p);
      if (p.deviceType != VK_PHYSICAL_DEVICE_TYPE_CPU) chosen = static_cast<int>(i);
    }
    if (chosen < 0) chosen = 0;
  }
  c->physical_ = devs[chosen];
  VkPhysicalDeviceProperties props;
  vkGetPhysicalDeviceProperties(c->physical_, &props);
  c->device_name_ = props.deviceName;
  c->max_storage_range_ = props.limits.maxStorageBufferRange;
  c->storage_limit_ = c->max_storage_range_;
  c->max_groups_[0] = props.limits.maxComputeWorkGroupCount[0];
  c->max_groups_[1] = props.limits.maxComputeWorkGroupCount[1];
  c->max_stage_storage_buffers_ = props.limits.maxPerStageDescriptorStorageBuffers;
  VkPhysicalDeviceDriverProperties drv{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES};
  VkPhysicalDeviceProperties2 p2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
  p2.pNext = &drv;
  vkGetPhysicalDeviceProperties2(c->physical_, &p2);
  c->driver_ = fmt::format("{} {}", drv.driverName, drv.driverInfo);
  vkGetPhysicalDeviceMemoryProperties(c->physical_, &c->memory_);

  std::uint32_t nf = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(c->physical_, &nf, nullptr);
  std::vector<VkQueueFamilyProperties> fams(nf);
  vkGetPhysicalDeviceQueueFamilyProperties(c->physical_, &nf, fams.data());
  bool found = false;
  for (std::uint32_t i = 0; i < nf && !found; ++i)
    if (fams[i].queueFlags & VK_QUEUE_COMPUTE_BIT) {
      c->family_ = i;
      found = true;
    }
  if (!found) return Status::Fail(fmt::format("Vulkan device '{}' has no compute queue", c->device_name_));

  VkPhysicalDeviceFeatures features{};
  features.shaderInt64 = VK_TRUE;
  const float priority = 1.0f;
  VkDeviceQueueCreateInfo qci{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
  qci.queueFamilyIndex = c->family_;
  qci.queueCount = 1;
  qci.pQueuePriorities = &priority;
  // 64-bit buffer atomics: the shade kernel's fixed-point accumulator.
  VkPhysicalDeviceVulkan12Features have12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
  VkPhysicalDeviceFeatures2 f2{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
  f2.pNext = &have12;
  vkGetPhysicalDeviceFeatures2(c->physical_, &f2);
  VkPhysicalDeviceVulkan12Features want12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
  want12.shaderBufferInt64Atomics = have12.shaderBufferInt64Atomics;
  VkDeviceCreateInfo dci{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
  dci.pNext = &want12;
  dci.queueCreateInfoCount = 1;
  dci.pQueueCreateInfos = &qci;
  dci.pEnabledFeatures = &features;
  RS_VK(vkCreateDevice(c->physical_, &dci, nullptr, &c->device_));
  vkGetDeviceQueue(c->device_, c->family_, 0, &c->queue_);
  VkCommandPoolCreateInfo pci{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
  pci.queueFamilyIndex = c->family_;
  pci.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
  RS_VK(vkCreateCommandPool(c->device_, &pci, nullptr, &c->pool_));
  out = std::move(c);
  return Status::Ok();
}

Context::~Context() {
  if (device_) {
    vkDeviceWaitIdle(device_);
    vkDestroyCommandPool(device_, pool_, nullptr);
    vkDestroyDevice(device_, nullptr);
  }
  if (instance_) vkDestroyInstance(instance_, nullptr);
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

std::uint32_t Context::FindMemoryType(std::uint32_t bits, VkMemoryPropertyFlags flags) const {
  for (std::uint32_t i = 0; i < memory_.memoryTypeCount; ++i)
    if ((bits & (1u << i)) && (memory_.memoryTypes[i].propertyFlags & flags) == flags) return i;
  return UINT32_MAX;
}

void Context::LimitForTesting(VkDeviceSize storage_bytes, std::uint32_t groups_x) {
  if (storage_bytes) storage_limit_ = std::min<VkDeviceSize>(storage_limit_, storage_bytes);
  if (groups_x) max_groups_[0] = std::min(max_groups_[0], groups_x);
}

Status Context::CreateBuffer(std::size_t bytes, Buffer& out, bool storage) {
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
  VkBufferCreateInfo bci{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
  bci.size = std::max<std::size_t>(bytes, 16);
  bci.usage = (storage ? VK_BUFFER_USAGE_STORAGE_BUFFER_BIT : 0) | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
  RS_VK(vkCreateBuffer(device_, &bci, nullptr, &b.buffer_));
  VkMemoryRequirements req;
  vkGetBufferMemoryRequirements(device_, b.buffer_, &req);
  const VkMemoryPropertyFlags want = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
  std::uint32_t type = UINT32_MAX;
  for (std::uint32_t i = 0; i < memory_.memoryTypeCount && type == UINT32_MAX; ++i)
    if ((req.memoryTypeBits & (1u << i)) && (memory_.memoryTypes[i].propertyFlags & want) == want) type = i;
  if (type == UINT32_MAX) return Status::Fail("no host-visible coherent memory type for a storage buffer");
  VkMemoryAllocateInfo mai{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
  mai.allocationSize = req.size;
  mai.memoryTypeIndex = type;
  RS_VK(vkAllocateMemory(device_, &mai, nullptr, &b.memory_));
  RS_VK(vkBindBufferMemory(device_, b.buffer_, b.memory_, 0));
  RS_VK(vkMapMemory(device_, b.memory_, 0, VK_WHOLE_SIZE, 0, &b.mapped_));
  out = std::move(b);
  return Status::Ok();
}

Status Context::CreateKernel(const std::string& name, std::span<const std::uint32_t> spirv, std::uint32_t bindings,
                             std::uint32_t fault, Kernel& k, std::uint32_t local_size) {
  // Paged arrays (paged.glsl) take several bindings each; a device with fewer is refused by name.
  if (bindings > max_stage_storage_buffers_)
    return Status::Fail(fmt::format("kernel {} needs {} storage-buffer bindings; '{}' allows {} (maxPerStageDescriptorStorageBuffers)",
                                    name, bindings, device_name_, max_stage_storage_buffers_));
  k.device_ = device_;
  k.local_size_ = local_size;
  k.name_ = name;
  k.bindings_ = bindings;
  VkShaderModuleCreateInfo smci{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
  smci.codeSize = spirv.size_bytes();
  smci.pCode = spirv.data();
  RS_VK(vkCreateShaderModule(device_, &smci, nullptr, &k.module_));
  std::vector<VkDescriptorSetLayoutBinding> b(bindings);
  for (std::uint32_t i = 0; i < bindings; ++i)
    b[i] = {i, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr};
  VkDescriptorSetLayoutCreateInfo dl{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
  dl.bindingCount = bindings;
  dl.pBindings = b.data();
  RS_VK(vkCreateDescriptorSetLayout(device_, &dl, nullptr, &k.set_layout_));
  VkPushConstantRange pcr{VK_SHADER_STAGE_COMPUTE_BIT, 0, 128};
  VkPipelineLayoutCreateInfo pl{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
  pl.setLayoutCount = 1;
  pl.pSetLayouts = &k.set_layout_;
  pl.pushConstantRangeCount = 1;
  pl.pPushConstantRanges = &pcr;
  RS_VK(vkCreatePipelineLayout(device_, &pl, nullptr, &k.layout_));
  const std::uint32_t spec[2] = {fault, k.local_size_};
  const VkSpecializationMapEntry entries[2] = {{0, 0, 4}, {1, 4, 4}};
  VkSpecializationInfo si{2, entries, sizeof spec, spec};
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

Recorder::~Recorder() {
  for (VkDescriptorPool p : pools_) vkDestroyDescriptorPool(ctx_.device_, p, nullptr);
  if (cmd_) vkFreeCommandBuffers(ctx_.device_, ctx_.pool_, 1, &cmd_);
}

Status Recorder::Begin() {
  if (!cmd_) {
    VkCommandBufferAllocateInfo ai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    ai.commandPool = ctx_.pool_;
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

Status Recorder::Dispatch(const Kernel& k, std::span<const Buffer* const> buffers, const void* push,
                          std::size_t push_size, std::uint32_t invocations) {
  if (!recording_) {
    Status s = Begin();
    if (!s) return s;
  }
  if (buffers.size() != k.bindings_) return Status::Fail(fmt::format("kernel {} takes {} buffers, got {}", k.name_, k.bindings_, buffers.size()));
  // A pass may record any number of parts before its submit: when the current descriptor pool has
  // no room for this set, the next one is used (and created once); all are reset after the submit.
  if (k.bindings_ > kPoolDescriptors) return Status::Fail(fmt::format("kernel {}: {} bindings exceed a descriptor pool", k.name_, k.bindings_));
  if (sets_left_ == 0 || descriptors_left_ < k.bindings_) {
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
  descriptors_left_ -= k.bindings_;
  VkDescriptorSetAllocateInfo ai{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
  ai.descriptorPool = pools_[current_];
  ai.descriptorSetCount = 1;
  ai.pSetLayouts = &k.set_layout_;
  VkDescriptorSet set;
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
  vkCmdBindPipeline(cmd_, VK_PIPELINE_BIND_POINT_COMPUTE, k.pipeline_);
  vkCmdBindDescriptorSets(cmd_, VK_PIPELINE_BIND_POINT_COMPUTE, k.layout_, 0, 1, &set, 0, nullptr);
  if (push_size) vkCmdPushConstants(cmd_, k.layout_, VK_SHADER_STAGE_COMPUTE_BIT, 0, static_cast<std::uint32_t>(push_size), push);
  // Launches wider than maxComputeWorkGroupCount[0] groups fold into rows of groups; kernels index
  // with GlobalIndex() (common.glsl), which reads the grid row-major, and skip indices past the end.
  const std::uint64_t groups = (std::uint64_t{invocations} + k.local_size_ - 1) / k.local_size_;
  const std::uint32_t gx = static_cast<std::uint32_t>(std::min<std::uint64_t>(groups, ctx_.max_groups_[0]));
  const std::uint64_t gy = gx ? (groups + gx - 1) / gx : 0;
  if (gy > ctx_.max_groups_[1])
    return Status::Fail(fmt::format("kernel {}: {} invocations need {} x {} workgroups, beyond maxComputeWorkGroupCount",
                                    k.name_, invocations, gx, gy));
  if (groups > 0) vkCmdDispatch(cmd_, gx, static_cast<std::uint32_t>(gy), 1);
  VkMemoryBarrier mb{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
  mb.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT;
  mb.dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_HOST_READ_BIT;
  vkCmdPipelineBarrier(cmd_, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT,
                       VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &mb, 0, nullptr, 0,
                       nullptr);
  return Status::Ok();
}

Status Recorder::Submit() {
  if (!recording_) return Status::Ok();
  RS_VK(vkEndCommandBuffer(cmd_));
  recording_ = false;
  if (Status st = ctx_.SubmitAndWait(cmd_); !st) return st;
  for (VkDescriptorPool p : pools_) RS_VK(vkResetDescriptorPool(ctx_.device_, p, 0));
  current_ = static_cast<std::size_t>(-1);
  sets_left_ = descriptors_left_ = 0;
  RS_VK(vkResetCommandBuffer(cmd_, 0));
  return Status::Ok();
}

}  // namespace rayspace::vk
