#include "rayspace/gpu/raster.h"

#include <fmt/format.h>

namespace rayspace::gpu_backend {
namespace {

#define RS_VK(call)                                                 \
  do {                                                              \
    const VkResult rs_r = (call);                                   \
    if (rs_r != VK_SUCCESS) return vk::Status::Fail(#call, rs_r);   \
  } while (0)

// Owns every object the raster pass creates, destroyed in reverse order.
struct RasterObjects {
  VkDevice dev = VK_NULL_HANDLE;
  VkImage images[2] = {};
  VkDeviceMemory memory[2] = {};
  VkImageView views[2] = {};
  VkRenderPass pass = VK_NULL_HANDLE;
  VkFramebuffer framebuffer = VK_NULL_HANDLE;
  VkShaderModule vert = VK_NULL_HANDLE, frag = VK_NULL_HANDLE;
  VkDescriptorSetLayout set_layout = VK_NULL_HANDLE;
  VkPipelineLayout layout = VK_NULL_HANDLE;
  VkPipeline pipeline = VK_NULL_HANDLE;
  VkDescriptorPool pool = VK_NULL_HANDLE;
  VkCommandBuffer cmd = VK_NULL_HANDLE;
  VkCommandPool cmd_pool = VK_NULL_HANDLE;
  VkFence fence = VK_NULL_HANDLE;
  ~RasterObjects() {
    if (!dev) return;
    if (fence) vkDestroyFence(dev, fence, nullptr);
    if (cmd) vkFreeCommandBuffers(dev, cmd_pool, 1, &cmd);
    if (pool) vkDestroyDescriptorPool(dev, pool, nullptr);
    if (pipeline) vkDestroyPipeline(dev, pipeline, nullptr);
    if (layout) vkDestroyPipelineLayout(dev, layout, nullptr);
    if (set_layout) vkDestroyDescriptorSetLayout(dev, set_layout, nullptr);
    if (vert) vkDestroyShaderModule(dev, vert, nullptr);
    if (frag) vkDestroyShaderModule(dev, frag, nullptr);
    if (framebuffer) vkDestroyFramebuffer(dev, framebuffer, nullptr);
    if (pass) vkDestroyRenderPass(dev, pass, nullptr);
    for (int i = 0; i < 2; ++i) {
      if (views[i]) vkDestroyImageView(dev, views[i], nullptr);
      if (images[i]) vkDestroyImage(dev, images[i], nullptr);
      if (memory[i]) vkFreeMemory(dev, memory[i], nullptr);
    }
  }
};

vk::Status MakeImage(vk::Context& ctx, RasterObjects& o, int i, VkFormat format, VkImageUsageFlags usage,
                     VkImageAspectFlags aspect, std::uint32_t w, std::uint32_t h) {
  VkImageCreateInfo ici{VK_STRUCTURE_TYPE_IMAGE_CREATE_INFO};
  ici.imageType = VK_IMAGE_TYPE_2D;
  ici.format = format;
  ici.extent = {w, h, 1};
  ici.mipLevels = 1;
  ici.arrayLayers = 1;
  ici.samples = VK_SAMPLE_COUNT_1_BIT;
  ici.tiling = VK_IMAGE_TILING_OPTIMAL;
  ici.usage = usage | VK_IMAGE_USAGE_TRANSFER_SRC_BIT;
  RS_VK(vkCreateImage(o.dev, &ici, nullptr, &o.images[i]));
  VkMemoryRequirements req;
  vkGetImageMemoryRequirements(o.dev, o.images[i], &req);
  VkMemoryAllocateInfo mai{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
  mai.allocationSize = req.size;
  mai.memoryTypeIndex = ctx.FindMemoryType(req.memoryTypeBits, 0);
  if (mai.memoryTypeIndex == UINT32_MAX) return vk::Status::Fail("no memory type for a raster image");
  RS_VK(vkAllocateMemory(o.dev, &mai, nullptr, &o.memory[i]));
  RS_VK(vkBindImageMemory(o.dev, o.images[i], o.memory[i], 0));
  VkImageViewCreateInfo vci{VK_STRUCTURE_TYPE_IMAGE_VIEW_CREATE_INFO};
  vci.image = o.images[i];
  vci.viewType = VK_IMAGE_VIEW_TYPE_2D;
  vci.format = format;
  vci.subresourceRange = {aspect, 0, 1, 0, 1};
  RS_VK(vkCreateImageView(o.dev, &vci, nullptr, &o.views[i]));
  return vk::Status::Ok();
}

}  // namespace

vk::Status RasterPrimitiveIds(vk::Context& ctx, std::span<const std::uint32_t> vert_spirv,
                              std::span<const std::uint32_t> frag_spirv, const gpu::FrameConstants& fc,
                              const std::vector<gpu::Triangle>& triangles, std::uint32_t fault,
                              std::vector<std::uint32_t>& prim, std::vector<float>& depth) {
  const std::uint32_t w = fc.dims.x, h = fc.dims.y;
  RasterObjects o;
  o.dev = ctx.device();
  o.cmd_pool = ctx.command_pool();
  vk::Status s = MakeImage(ctx, o, 0, VK_FORMAT_R32_UINT, VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT, VK_IMAGE_ASPECT_COLOR_BIT, w, h);
  if (!s) return s;
  s = MakeImage(ctx, o, 1, VK_FORMAT_D32_SFLOAT, VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT, VK_IMAGE_ASPECT_DEPTH_BIT, w, h);
  if (!s) return s;

  VkAttachmentDescription att[2] = {};
  att[0].format = VK_FORMAT_R32_UINT;
  att[1].format = VK_FORMAT_D32_SFLOAT;
  for (auto& a : att) {
    a.samples = VK_SAMPLE_COUNT_1_BIT;
    a.loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
    a.storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    a.stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
    a.stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
    a.initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    a.finalLayout = VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL;
  }
  VkAttachmentReference color_ref{0, VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL};
  VkAttachmentReference depth_ref{1, VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL};
  VkSubpassDescription sub{};
  sub.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
  sub.colorAttachmentCount = 1;
  sub.pColorAttachments = &color_ref;
  sub.pDepthStencilAttachment = &depth_ref;
  VkRenderPassCreateInfo rpci{VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO};
  rpci.attachmentCount = 2;
  rpci.pAttachments = att;
  rpci.subpassCount = 1;
  rpci.pSubpasses = &sub;
  RS_VK(vkCreateRenderPass(o.dev, &rpci, nullptr, &o.pass));
  VkFramebufferCreateInfo fci{VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO};
  fci.renderPass = o.pass;
  fci.attachmentCount = 2;
  fci.pAttachments = o.views;
  fci.width = w;
  fci.height = h;
  fci.layers = 1;
  RS_VK(vkCreateFramebuffer(o.dev, &fci, nullptr, &o.framebuffer));

  VkShaderModuleCreateInfo smci{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
  smci.codeSize = vert_spirv.size_bytes();
  smci.pCode = vert_spirv.data();
  RS_VK(vkCreateShaderModule(o.dev, &smci, nullptr, &o.vert));
  smci.codeSize = frag_spirv.size_bytes();
  smci.pCode = frag_spirv.data();
  RS_VK(vkCreateShaderModule(o.dev, &smci, nullptr, &o.frag));
  VkDescriptorSetLayoutBinding b[2] = {
      {0, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, nullptr},
      {1, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, nullptr}};
  VkDescriptorSetLayoutCreateInfo dl{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
  dl.bindingCount = 2;
  dl.pBindings = b;
  RS_VK(vkCreateDescriptorSetLayout(o.dev, &dl, nullptr, &o.set_layout));
  VkPipelineLayoutCreateInfo pl{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
  pl.setLayoutCount = 1;
  pl.pSetLayouts = &o.set_layout;
  RS_VK(vkCreatePipelineLayout(o.dev, &pl, nullptr, &o.layout));

  VkPipelineShaderStageCreateInfo stages[2] = {{VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO},
                                               {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO}};
  stages[0].stage = VK_SHADER_STAGE_VERTEX_BIT;
  stages[0].module = o.vert;
  stages[0].pName = "main";
  stages[1].stage = VK_SHADER_STAGE_FRAGMENT_BIT;
  stages[1].module = o.frag;
  stages[1].pName = "main";
  const VkSpecializationMapEntry fault_entry{0, 0, 4};
  const VkSpecializationInfo fault_info{1, &fault_entry, sizeof fault, &fault};
  stages[1].pSpecializationInfo = &fault_info;
  VkPipelineVertexInputStateCreateInfo vi{VK_STRUCTURE_TYPE_PIPELINE_VERTEX_INPUT_STATE_CREATE_INFO};
  VkPipelineInputAssemblyStateCreateInfo ia{VK_STRUCTURE_TYPE_PIPELINE_INPUT_ASSEMBLY_STATE_CREATE_INFO};
  ia.topology = VK_PRIMITIVE_TOPOLOGY_TRIANGLE_LIST;
  VkViewport viewport{0.0f, 0.0f, static_cast<float>(w), static_cast<float>(h), 0.0f, 1.0f};
  VkRect2D scissor{{0, 0}, {w, h}};
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
  VkPipelineColorBlendAttachmentState cba{};
  cba.colorWriteMask = VK_COLOR_COMPONENT_R_BIT;
  VkPipelineColorBlendStateCreateInfo cb{VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO};
  cb.attachmentCount = 1;
  cb.pAttachments = &cba;
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
  gp.layout = o.layout;
  gp.renderPass = o.pass;
  RS_VK(vkCreateGraphicsPipelines(o.dev, VK_NULL_HANDLE, 1, &gp, nullptr, &o.pipeline));

  vk::Buffer tri_buf, fc_buf, prim_buf, depth_buf;
  if (vk::Status st = ctx.CreateBuffer(triangles.size() * sizeof(gpu::Triangle), tri_buf); !st) return st;
  tri_buf.Upload(triangles);
  if (vk::Status st = ctx.CreateBuffer(sizeof(gpu::FrameConstants), fc_buf); !st) return st;
  fc_buf.Upload(std::vector<gpu::FrameConstants>{fc});
  const std::size_t pixels = static_cast<std::size_t>(w) * h;
  if (vk::Status st = ctx.CreateBuffer(pixels * 4, prim_buf); !st) return st;
  if (vk::Status st = ctx.CreateBuffer(pixels * 4, depth_buf); !st) return st;

  VkDescriptorPoolSize ps{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 2};
  VkDescriptorPoolCreateInfo dp{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
  dp.maxSets = 1;
  dp.poolSizeCount = 1;
  dp.pPoolSizes = &ps;
  RS_VK(vkCreateDescriptorPool(o.dev, &dp, nullptr, &o.pool));
  VkDescriptorSetAllocateInfo dai{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
  dai.descriptorPool = o.pool;
  dai.descriptorSetCount = 1;
  dai.pSetLayouts = &o.set_layout;
  VkDescriptorSet set;
  RS_VK(vkAllocateDescriptorSets(o.dev, &dai, &set));
  VkDescriptorBufferInfo infos[2] = {{tri_buf.handle(), 0, VK_WHOLE_SIZE}, {fc_buf.handle(), 0, VK_WHOLE_SIZE}};
  VkWriteDescriptorSet writes[2] = {{VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET}, {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET}};
  for (int i = 0; i < 2; ++i) {
    writes[i].dstSet = set;
    writes[i].dstBinding = static_cast<std::uint32_t>(i);
    writes[i].descriptorCount = 1;
    writes[i].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    writes[i].pBufferInfo = &infos[i];
  }
  vkUpdateDescriptorSets(o.dev, 2, writes, 0, nullptr);

  VkCommandBufferAllocateInfo cai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  cai.commandPool = o.cmd_pool;
  cai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  cai.commandBufferCount = 1;
  RS_VK(vkAllocateCommandBuffers(o.dev, &cai, &o.cmd));
  VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  RS_VK(vkBeginCommandBuffer(o.cmd, &bi));
  VkClearValue clears[2];
  clears[0].color.uint32[0] = gpu::kNoPrim;
  clears[0].color.uint32[1] = clears[0].color.uint32[2] = clears[0].color.uint32[3] = 0;
  clears[1].depthStencil = {1.0f, 0};
  VkRenderPassBeginInfo rbi{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
  rbi.renderPass = o.pass;
  rbi.framebuffer = o.framebuffer;
  rbi.renderArea = {{0, 0}, {w, h}};
  rbi.clearValueCount = 2;
  rbi.pClearValues = clears;
  vkCmdBeginRenderPass(o.cmd, &rbi, VK_SUBPASS_CONTENTS_INLINE);
  vkCmdBindPipeline(o.cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, o.pipeline);
  vkCmdBindDescriptorSets(o.cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, o.layout, 0, 1, &set, 0, nullptr);
  vkCmdDraw(o.cmd, static_cast<std::uint32_t>(3 * triangles.size()), 1, 0, 0);
  vkCmdEndRenderPass(o.cmd);
  VkBufferImageCopy copy{};
  copy.imageSubresource = {VK_IMAGE_ASPECT_COLOR_BIT, 0, 0, 1};
  copy.imageExtent = {w, h, 1};
  vkCmdCopyImageToBuffer(o.cmd, o.images[0], VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, prim_buf.handle(), 1, &copy);
  copy.imageSubresource.aspectMask = VK_IMAGE_ASPECT_DEPTH_BIT;
  vkCmdCopyImageToBuffer(o.cmd, o.images[1], VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, depth_buf.handle(), 1, &copy);
  VkMemoryBarrier mb{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
  mb.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
  mb.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
  vkCmdPipelineBarrier(o.cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &mb, 0, nullptr, 0, nullptr);
  RS_VK(vkEndCommandBuffer(o.cmd));
  VkFenceCreateInfo fci2{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
  RS_VK(vkCreateFence(o.dev, &fci2, nullptr, &o.fence));
  VkSubmitInfo si{VK_STRUCTURE_TYPE_SUBMIT_INFO};
  si.commandBufferCount = 1;
  si.pCommandBuffers = &o.cmd;
  RS_VK(vkQueueSubmit(ctx.queue(), 1, &si, o.fence));
  RS_VK(vkWaitForFences(o.dev, 1, &o.fence, VK_TRUE, UINT64_MAX));
  prim = prim_buf.Download<std::uint32_t>(pixels);
  depth = depth_buf.Download<float>(pixels);
  return vk::Status::Ok();
}

}  // namespace rayspace::gpu_backend
