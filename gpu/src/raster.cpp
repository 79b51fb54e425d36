#include "rayspace/gpu/raster.h"

#include "raster_frag.spv.h"
#include "raster_vert.spv.h"
#include "rayspace/emu/passes.h"
#include "rayspace/gpu/passes.h"

#include <fmt/format.h>

namespace rayspace::gpu_backend {
namespace {

constexpr int kColors = static_cast<int>(std::size(kRasterColorFormats));
constexpr int kTargets = kColors + 1;  // and the depth attachment, last
constexpr std::size_t kTexelBytes[kTargets] = {16, 16, 16, 16, 4, 4};
// The storage buffers both stages read: triangles, frame, normals, info, materials.
constexpr std::uint32_t kBindings = 5;

// The attachments and the host-visible buffers they are copied into.
struct Targets {
  vk::Image images[kTargets];
  vk::Buffer readback[kTargets];
};

vk::Status MakeTargets(vk::Context& ctx, std::uint32_t w, std::uint32_t h, Targets& t) {
  const std::size_t pixels = static_cast<std::size_t>(w) * h;
  for (int i = 0; i < kTargets; ++i) {
    const bool depth = i == kColors;
    vk::Status s = ctx.CreateImage(depth ? kRasterDepthFormat : kRasterColorFormats[i],
                                   depth ? VK_IMAGE_USAGE_DEPTH_STENCIL_ATTACHMENT_BIT : VK_IMAGE_USAGE_COLOR_ATTACHMENT_BIT,
                                   depth ? VK_IMAGE_ASPECT_DEPTH_BIT : VK_IMAGE_ASPECT_COLOR_BIT, w, h, t.images[i]);
    if (!s) return s;
    if (vk::Status st = ctx.CreateBuffer(pixels * kTexelBytes[i], t.readback[i], /*storage=*/false); !st) return st;
  }
  return vk::Status::Ok();
}

vk::Status MakePipeline(vk::Context& ctx, std::span<const std::uint32_t> vert_spirv,
                        std::span<const std::uint32_t> frag_spirv, std::uint32_t fault, std::uint32_t w, std::uint32_t h,
                        const Targets& t, const RasterViolations& planted, vk::Graphics& out) {
  vk::GraphicsDesc d;
  d.name = "raster";
  d.vert_spirv = vert_spirv;
  d.frag_spirv = frag_spirv;
  d.bindings = kBindings;
  d.fault = fault;
  d.colors = kRasterColorFormats;
  d.depth = kRasterDepthFormat;
  d.drop_dependencies_for_testing = planted.drop_subpass_dependencies;
  d.differing_blend_for_testing = planted.differing_blend_states;
  d.width = w;
  d.height = h;
  const vk::Image* attachments[kTargets];
  for (int i = 0; i < kTargets; ++i) attachments[i] = &t.images[i];
  return ctx.CreateGraphics(d, attachments, out);
}

template <typename T>
vk::Status Upload(vk::Context& ctx, const std::vector<T>& v, vk::Buffer& out) {
  if (vk::Status st = ctx.CreateBuffer(v.size() * sizeof(T), out); !st) return st;
  return out.Upload(v);
}

// The scene in binding order.
vk::Status UploadInputs(vk::Context& ctx, const layout::FrameConstants& fc, const SceneBuffers& scene,
                        vk::Buffer (&in)[kBindings]) {
  for (vk::Status st : {Upload(ctx, scene.triangles, in[0]), Upload(ctx, std::vector<layout::FrameConstants>{fc}, in[1]),
                        Upload(ctx, scene.normals, in[2]), Upload(ctx, scene.info, in[3]),
                        Upload(ctx, scene.materials, in[4])})
    if (!st) return st;
  return vk::Status::Ok();
}

// Draws every triangle into cleared targets (no primitive, depth 1) and copies them to the host.
vk::Status DrawAndRead(vk::Context& ctx, const vk::Graphics& g, const vk::Buffer (&in)[kBindings],
                       std::size_t triangles, const Targets& t) {
  VkClearValue clears[kTargets] = {};
  clears[4].color.uint32[0] = layout::kNoPrim;
  clears[kColors].depthStencil = {1.0f, 0};
  const vk::Buffer* const buffers[kBindings] = {&in[0], &in[1], &in[2], &in[3], &in[4]};
  vk::Recorder rec(ctx);
  if (vk::Status st = rec.Draw(g, buffers, clears, static_cast<std::uint32_t>(3 * triangles)); !st) return st;
  for (int i = 0; i < kTargets; ++i)
    if (vk::Status st = rec.CopyToHost(t.images[i], t.readback[i]); !st) return st;
  return rec.Submit();
}

vk::Status Download(const Targets& t, std::uint32_t w, std::uint32_t h, emu::GBuffer& out) {
  const std::size_t pixels = static_cast<std::size_t>(w) * h;
  out.width = static_cast<int>(w);
  out.height = static_cast<int>(h);
  RS_TRY(t.readback[0].Download(pixels, out.diffuse));
  RS_TRY(t.readback[1].Download(pixels, out.specular));
  RS_TRY(t.readback[2].Download(pixels, out.position));
  RS_TRY(t.readback[3].Download(pixels, out.normal));
  RS_TRY(t.readback[4].Download(pixels, out.prim));
  RS_TRY(t.readback[5].Download(pixels, out.depth));
  return vk::Status::Ok();
}

}  // namespace

vk::Status RasterGBuffer(vk::Context& ctx, std::span<const std::uint32_t> vert_spirv,
                         std::span<const std::uint32_t> frag_spirv, const layout::FrameConstants& fc, const SceneBuffers& scene,
                         std::uint32_t fault, emu::GBuffer& out, const RasterViolations& planted) {
  const std::uint32_t w = fc.dims.x, h = fc.dims.y;
  Targets t;
  if (vk::Status st = MakeTargets(ctx, w, h, t); !st) return st;
  vk::Graphics g;
  if (vk::Status st = MakePipeline(ctx, vert_spirv, frag_spirv, fault, w, h, t, planted, g); !st) return st;
  vk::Buffer in[kBindings];
  if (vk::Status st = UploadInputs(ctx, fc, scene, in); !st) return st;
  if (vk::Status st = DrawAndRead(ctx, g, in, scene.triangles.size(), t); !st) return st;
  return Download(t, w, h, out);
}

vk::Status VulkanPasses::Run(const emu::call::Raster& c, emu::GBuffer& out) {
  // The simulated device has no graphics pipeline: its raster is the emulator's.
  if (ctx_->simulated()) {
    out = emu::PassRaster(c);
    return vk::Status::Ok();
  }
  return RasterGBuffer(*ctx_, kSpirv_raster_vert, kSpirv_raster_frag, c.frame, *c.scene, raster_fault_, out);
}

}  // namespace rayspace::gpu_backend
