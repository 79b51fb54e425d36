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
  static constexpr int kImages = 6;  // 4 x RGBA32F, R32UI, D32
  VkImage images[kImages] = {};
  VkDeviceMemory memory[kImages] = {};
  VkImageView views[kImages] = {};
  VkRenderPass pass = VK_NULL_HANDLE;
  VkFramebuffer framebuffer = VK_NULL_HANDLE;
  VkShaderModule vert = VK_NULL_HANDLE, frag = VK_NULL_HANDLE;
  VkDescriptorSetLayout set_layout = VK_NULL_HANDLE;
  VkPipelineLayout layout = VK_NULL_HANDLE;
  VkPipeline pipeline = VK_NULL_HANDLE;
  VkDescriptorPool pool = VK_NULL_HANDLE;
  VkCommandBuffer cmd = VK_NULL_HANDLE;
  VkCommandPool cmd_pool = VK_NULL_HANDLE;
  ~RasterObjects() {
    if (!dev) return;
    if (cmd) vkFreeCommandBuffers(dev, cmd_pool, 1, &cmd);
    if (pool) vkDestroyDescriptorPool(dev, pool, nullptr);
    if (pipeline) vkDestroyPipeline(dev, pipeline, nullptr);
    if (layout) vkDestroyPipelineLayout(dev, layout, nullptr);
    if (set_layout) vkDestroyDescriptorSetLayout(dev, set_layout, nullptr);
    if (vert) vkDestroyShaderModule(dev, vert, nullptr);
    if (frag) vkDestroyShaderModule(dev, frag, nullptr);
    if (framebuffer) vkDestroyFramebuffer(dev, framebuffer, nullptr);
    if (pass) vkDestroyRenderPass(dev, pass, nullptr);
    for (int i = 0; i < kImages; ++i) {
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

vk::Status RasterGBuffer(vk::Context& ctx, std::span<const std::uint32_t> vert_spirv,
                         std::span<const std::uint32_t> frag_spirv, const gpu::FrameConstants& fc, const SceneBuffers& scene,
                         std::uint32_t fault, RasterTargets& out) {
  const std::vector<gpu::Triangle>& triangles = scene.triangles;
  const std::uint32_t w = fc.dims.x, h = fc.dims.y;
  constexpr int kColors = 5;
  const VkFormat formats[6] = {VK_FORMAT_R32G32B32A32_SFLOAT, VK_FORMAT_R32G32B32A32_SFLOAT, VK_FORMAT_R32G32B32A32_SFLOAT,
                               VK_FORMAT_R32G32B32A32_SFLOAT, VK_FORMAT_R32_UINT, VK_FORMAT_D32_SFLOAT};
  RasterObjects o;
  o.dev = ctx.device();
  o.cmd_pool = ctx.command_pool();
  for (int i = 0; i < 6; ++i) {
    const bool depth_image = i == kColors;
    vk::Status s = MakeImage(ctx, o, i, formats[i],
                             depth_image ? VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT : VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT,
                             depth_image ? VK_IMAGE_ASPECT_DEPTH_BIT : VK_IMAGE_ASPECT_COLOR_BIT, w, h);
    if (!s) return s;
  }

  VkAttachmentDescription att[6] = {};
  VkAttachmentReference color_ref[kColors];
  for (int i = 0; i < 6; ++i) {
    att[i].format = formats[i];
    att[i].samples = VK_SAMPLE_COUNT_1_BIT;
    att[i].loadOp = VK_ATTACHMENT_LOAD_OP_CLEAR;
    att[i].storeOp = VK_ATTACHMENT_STORE_OP_STORE;
    att[i].stencilLoadOp = VK_ATTACHMENT_LOAD_OP_DONT_CARE;
    att[i].stencilStoreOp = VK_ATTACHMENT_STORE_OP_DONT_CARE;
    att[i].initialLayout = VK_IMAGE_LAYOUT_UNDEFINED;
    att[i].finalLayout = VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL;
    if (i < kColors) color_ref[i] = {static_cast<std::uint32_t>(i), VK_IMAGE_LAYOUT_COLOR_ATTACHMENT_OPTIMAL};
  }
  VkAttachmentReference depth_ref{kColors, VK_IMAGE_LAYOUT_DEPTH_STENCIL_ATTACHMENT_OPTIMAL};
  VkSubpassDescription sub{};
  sub.pipelineBindPoint = VK_PIPELINE_BIND_POINT_GRAPHICS;
  sub.colorAttachmentCount = kColors;
  sub.pColorAttachments = color_ref;
  sub.pDepthStencilAttachment = &depth_ref;
  VkRenderPassCreateInfo rpci{VK_STRUCTURE_TYPE_RENDER_PASS_CREATE_INFO};
  rpci.attachmentCount = 6;
  rpci.pAttachments = att;
  rpci.subpassCount = 1;
  rpci.pSubpasses = &sub;
  RS_VK(vkCreateRenderPass(o.dev, &rpci, nullptr, &o.pass));
  VkFramebufferCreateInfo fci{VK_STRUCTURE_TYPE_FRAMEBUFFER_CREATE_INFO};
  fci.renderPass = o.pass;
  fci.attachmentCount = 6;
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
  constexpr std::uint32_t kBindings = 5;  // triangles, frame, normals, info, materials
  VkDescriptorSetLayoutBinding b[kBindings];
  for (std::uint32_t i = 0; i < kBindings; ++i)
    b[i] = {i, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT, nullptr};
  VkDescriptorSetLayoutCreateInfo dl{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
  dl.bindingCount = kBindings;
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
  VkPipelineColorBlendAttachmentState cba[kColors] = {};
  for (int i = 0; i < kColors; ++i)
    cba[i].colorWriteMask = i == 4 ? VK_COLOR_COMPONENT_R_BIT
                                   : VK_COLOR_COMPONENT_R_BIT | VK_COLOR_COMPONENT_G_BIT | VK_COLOR_COMPONENT_B_BIT | VK_COLOR_COMPONENT_A_BIT;
  VkPipelineColorBlendStateCreateInfo cb{VK_STRUCTURE_TYPE_PIPELINE_COLOR_BLEND_STATE_CREATE_INFO};
  cb.attachmentCount = kColors;
  cb.pAttachments = cba;
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

  vk::Buffer in[kBindings];
  auto upload = [&](vk::Buffer& buf, const auto& v) -> vk::Status {
    if (vk::Status st = ctx.CreateBuffer(v.size() * sizeof(v[0]), buf); !st) return st;
    buf.Upload(v);
    return vk::Status::Ok();
  };
  for (vk::Status st : {upload(in[0], triangles), upload(in[1], std::vector<gpu::FrameConstants>{fc}),
                        upload(in[2], scene.normals), upload(in[3], scene.info), upload(in[4], scene.materials)})
    if (!st) return st;
  const std::size_t pixels = static_cast<std::size_t>(w) * h;
  vk::Buffer outb[6];
  for (int i = 0; i < 6; ++i) {
    const std::size_t texel = i < 4 ? 16 : 4;
    if (vk::Status st = ctx.CreateBuffer(pixels * texel, outb[i], /*storage=*/false); !st) return st;
  }

  VkDescriptorPoolSize ps{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, kBindings};
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
  VkDescriptorBufferInfo infos[kBindings];
  VkWriteDescriptorSet writes[kBindings];
  for (std::uint32_t i = 0; i < kBindings; ++i) {
    infos[i] = {in[i].handle(), 0, VK_WHOLE_SIZE};
    writes[i] = {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
    writes[i].dstSet = set;
    writes[i].dstBinding = static_cast<std::uint32_t>(i);
    writes[i].descriptorCount = 1;
    writes[i].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
    writes[i].pBufferInfo = &infos[i];
  }
  vkUpdateDescriptorSets(o.dev, kBindings, writes, 0, nullptr);

  VkCommandBufferAllocateInfo cai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  cai.commandPool = o.cmd_pool;
  cai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  cai.commandBufferCount = 1;
  RS_VK(vkAllocateCommandBuffers(o.dev, &cai, &o.cmd));
  VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  RS_VK(vkBeginCommandBuffer(o.cmd, &bi));
  VkClearValue clears[6] = {};
  clears[4].color.uint32[0] = gpu::kNoPrim;
  clears[5].depthStencil = {1.0f, 0};
  VkRenderPassBeginInfo rbi{VK_STRUCTURE_TYPE_RENDER_PASS_BEGIN_INFO};
  rbi.renderPass = o.pass;
  rbi.framebuffer = o.framebuffer;
  rbi.renderArea = {{0, 0}, {w, h}};
  rbi.clearValueCount = 6;
  rbi.pClearValues = clears;
  vkCmdBeginRenderPass(o.cmd, &rbi, VK_SUBPASS_CONTENTS_INLINE);
  vkCmdBindPipeline(o.cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, o.pipeline);
  vkCmdBindDescriptorSets(o.cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, o.layout, 0, 1, &set, 0, nullptr);
  vkCmdDraw(o.cmd, static_cast<std::uint32_t>(3 * triangles.size()), 1, 0, 0);
  vkCmdEndRenderPass(o.cmd);
  for (int i = 0; i < 6; ++i) {
    VkBufferImageCopy copy{};
    copy.imageSubresource = {i == kColors ? VkImageAspectFlags(VK_IMAGE_ASPECT_DEPTH_BIT) : VkImageAspectFlags(VK_IMAGE_ASPECT_COLOR_BIT), 0, 0, 1};
    copy.imageExtent = {w, h, 1};
    vkCmdCopyImageToBuffer(o.cmd, o.images[i], VK_IMAGE_LAYOUT_TRANSFER_SRC_OPTIMAL, outb[i].handle(), 1, &copy);
  }
  VkMemoryBarrier mb{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
  mb.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
  mb.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
  vkCmdPipelineBarrier(o.cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &mb, 0, nullptr, 0, nullptr);
  RS_VK(vkEndCommandBuffer(o.cmd));
  if (vk::Status st = ctx.SubmitAndWait(o.cmd); !st) return st;
  out.diffuse = outb[0].Download<glm::vec4>(pixels);
  out.specular = outb[1].Download<glm::vec4>(pixels);
  out.position = outb[2].Download<glm::vec4>(pixels);
  out.normal = outb[3].Download<glm::vec4>(pixels);
  out.prim = outb[4].Download<std::uint32_t>(pixels);
  out.depth = outb[5].Download<float>(pixels);
  return vk::Status::Ok();
}

}  // namespace rayspace::gpu_backend
