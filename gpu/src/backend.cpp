#include "rayspace/gpu/backend.h"

#include <fmt/format.h>

#include "rayspace/error.h"
#include "rayspace/scene_buffers.h"

namespace rayspace::gpu_backend {
namespace {

void Check(const char* pass, const vk::Status& s) {
  if (!s) throw emu::BackendError(fmt::format("Vulkan backend, pass {}: {}", pass, s.message));
}

std::vector<std::uint32_t> Widen(const std::vector<std::uint8_t>& v) { return {v.begin(), v.end()}; }

// Kernels write 32-bit flags; the emulated passes' byte flags hold 0/1 (or a child count <= 16).
std::vector<std::uint8_t> Narrow(const char* pass, const std::vector<std::uint32_t>& v) {
  std::vector<std::uint8_t> out(v.size());
  for (std::size_t i = 0; i < v.size(); ++i) {
    if (v[i] > 0xFFu) throw emu::BackendError(fmt::format("Vulkan backend, pass {}: element {} is {}, not a flag", pass, i, v[i]));
    out[i] = static_cast<std::uint8_t>(v[i]);
  }
  return out;
}

class VulkanFrame final : public emu::FramePasses {
 public:
  explicit VulkanFrame(VulkanPasses& gpu) : gpu_(gpu) {}
  std::string Name() const override { return "vulkan"; }
  emu::GBuffer Raster(const gpu::FrameConstants& fc, const SceneBuffers& scene) override {
    emu::GBuffer g;
    Check("raster", gpu_.Raster(fc, scene, g));
    return g;
  }
  std::vector<gpu::Surface> SurfacesFromGBuffer(const gpu::FrameConstants& fc, const emu::GBuffer& g,
                                                const SceneBuffers& scene) override {
    std::vector<gpu::Surface> s;
    Check("surfaces", gpu_.Surfaces(fc, g, scene, s));
    return s;
  }
  std::vector<gpu::Surface> SurfacesFromHits(const std::vector<gpu::Ray>& rays, const std::vector<std::uint64_t>& hits,
                                             const SceneBuffers& scene) override {
    std::vector<gpu::Surface> s;
    Check("surfaces.hits", gpu_.SurfacesFromHits(rays, hits, scene, s));
    return s;
  }
  emu::SparseRays Raygen(std::uint32_t kind, const gpu::FrameConstants& fc, const std::vector<gpu::Surface>& surfaces,
                         const SceneBuffers& scene) override {
    emu::SparseRays r;
    switch (kind) {
      case gpu::kRayShadow: Check("raygen.shadow", gpu_.RaygenShadow(fc, surfaces, scene, r)); break;
      case gpu::kRayReflection: Check("raygen.reflection", gpu_.RaygenReflection(fc, surfaces, scene, r)); break;
      case gpu::kRayRefraction: Check("raygen.refraction", gpu_.RaygenRefraction(fc, surfaces, scene, r)); break;
      default: RS_CHECK_MSG(false, "unknown ray kind {}", kind);
    }
    return r;
  }
  emu::Trimmed Trim(std::uint32_t /*kind: one kernel trims every kind*/, const emu::SparseRays& sparse) override {
    emu::Trimmed t;
    Check("trim", gpu_.Trim(sparse, t));
    return t;
  }
  void Shade(const gpu::FrameConstants&, const std::vector<gpu::Surface>& surfaces,
             const std::vector<std::uint32_t>& shadow_flags, const std::vector<std::uint32_t>& shadow_offsets,
             const std::vector<std::uint32_t>& occluded, const SceneBuffers& scene,
             std::vector<std::uint64_t>& accum) override {
    Check("shade", gpu_.Shade(surfaces, shadow_flags, shadow_offsets, occluded, scene, accum));
  }
  std::vector<std::uint8_t> Resolve(const gpu::FrameConstants& fc, const std::vector<std::uint64_t>& accum) override {
    std::vector<std::uint8_t> rgb;
    Check("resolve", gpu_.Resolve(fc, accum, rgb));
    return rgb;
  }

 private:
  VulkanPasses& gpu_;
};

class VulkanHierarchy final : public emu::HierarchyPasses {
 public:
  explicit VulkanHierarchy(VulkanPasses& gpu) : gpu_(gpu) {}
  std::string Name() const override { return "vulkan"; }
  std::vector<std::uint32_t> Hash(const std::vector<gpu::Ray>& rays, const SceneBuffers& scene, const emu::HashConfig& h,
                                  std::uint32_t quadtree_width, int quadtree_depth) override {
    // The kernel reads the scene box from the frame constants; nothing else of them.
    gpu::FrameConstants fc{};
    fc.scene_lo = glm::vec4(scene.lo, 0.0f);
    fc.scene_hi = glm::vec4(scene.hi, 0.0f);
    std::vector<std::uint32_t> keys;
    Check("hash", gpu_.Hash(rays, fc, h, keys, quadtree_width, static_cast<std::uint32_t>(quadtree_depth)));
    return keys;
  }
  emu::Chunks Compress(const std::vector<std::uint32_t>& keys) override {
    emu::Chunks c;
    Check("compress", gpu_.Compress(keys, c));
    return c;
  }
  std::vector<std::uint32_t> SortChunks(const std::vector<std::uint32_t>& chunk_keys) override {
    std::vector<std::uint32_t> s;
    Check("sort", gpu_.SortChunks(chunk_keys, s));
    return s;
  }
  std::vector<std::uint32_t> Decompress(const emu::Chunks& chunks, const std::vector<std::uint32_t>& sorted) override {
    std::vector<std::uint32_t> o;
    Check("decompress", gpu_.Decompress(chunks, sorted, o));
    return o;
  }
  std::vector<gpu::ConeNode> BuildLeaves(const std::vector<gpu::Ray>& rays, const std::vector<std::uint32_t>& order,
                                         const std::vector<std::uint32_t>& first) override {
    std::vector<gpu::ConeNode> n;
    Check("build", gpu_.BuildLeaves(rays, order, first, n));
    return n;
  }
  std::vector<gpu::ConeNode> BuildParents(const std::vector<gpu::ConeNode>& below,
                                          const std::vector<std::uint32_t>& first) override {
    std::vector<gpu::ConeNode> n;
    Check("build", gpu_.BuildParents(below, first, n));
    return n;
  }
  std::vector<std::uint8_t> ObjectMask(const std::vector<gpu::ConeNode>& top, const std::vector<glm::vec4>& object_spheres,
                                       float eps) override {
    std::vector<std::uint32_t> m;
    Check("traverse.objects", gpu_.ObjectMask(top, object_spheres, eps, m));
    return Narrow("traverse.objects", m);
  }
  emu::PairSlots TraverseTop(const std::vector<gpu::ConeNode>& top, std::uint32_t t0, std::uint32_t t1, std::uint32_t b0,
                             std::uint32_t b1, const std::vector<glm::vec4>& tri_spheres, const SceneBuffers& scene,
                             const std::vector<std::uint8_t>& object_mask, float eps) override {
    std::vector<std::uint32_t> f, v, t;
    Check("traverse", gpu_.TraverseTop(top, t0, t1, b0, b1, tri_spheres, scene, eps, Widen(object_mask), f, v, t));
    return {Narrow("traverse", f), std::move(v), Narrow("traverse", t)};
  }
  emu::PairSlots TraverseLevel(const std::vector<std::uint32_t>& pairs, const std::vector<gpu::ConeNode>& nodes,
                               const std::vector<std::uint32_t>& first, std::uint32_t base_up, std::uint32_t base,
                               std::uint32_t children_max, std::uint32_t b0, const std::vector<glm::vec4>& tri_spheres,
                               float eps) override {
    std::vector<std::uint32_t> f, v, t;
    Check("traverse", gpu_.TraverseLevel(pairs, nodes, first, base_up, base, children_max, b0, tri_spheres, eps, f, v, t));
    return {Narrow("traverse", f), std::move(v), Narrow("traverse", t)};
  }
  std::vector<std::uint32_t> Reduce(emu::Reduction reduction, int component, const std::vector<std::uint8_t>& flags,
                                    const std::vector<std::uint32_t>& values) override {
    std::vector<std::uint32_t> out;
    if (reduction == emu::Reduction::kHierarchical)
      Check("reduce", gpu_.Reduce(Widen(flags), values, static_cast<std::uint32_t>(component), out));
    else
      Check("reduce", gpu_.ReduceScan(Widen(flags), values, out));
    return out;
  }
  std::vector<std::uint32_t> Intersect(const std::vector<std::uint32_t>& pairs, const std::vector<std::uint32_t>& first1,
                                       std::uint32_t base1, std::uint32_t b0, const std::vector<std::uint32_t>& order,
                                       const std::vector<gpu::Ray>& rays, const SceneBuffers& scene,
                                       std::vector<std::uint64_t>* hits, std::vector<std::uint32_t>* occluded) override {
    std::vector<std::uint64_t> h;
    std::vector<std::uint32_t> o, tests;
    Check("intersect", gpu_.Intersect(pairs, first1, base1, b0, order, rays, scene, occluded != nullptr, h, o, tests));
    // The kernel starts from empty results; merge into the caller's (min for hits, or for occlusion).
    if (hits)
      for (std::size_t i = 0; i < h.size(); ++i) (*hits)[i] = std::min((*hits)[i], h[i]);
    if (occluded)
      for (std::size_t i = 0; i < o.size(); ++i) (*occluded)[i] |= o[i];
    return tests;
  }

 private:
  VulkanPasses& gpu_;
};

}  // namespace

std::unique_ptr<emu::FramePasses> MakeVulkanFramePasses(VulkanPasses& gpu) { return std::make_unique<VulkanFrame>(gpu); }
std::unique_ptr<emu::HierarchyPasses> MakeVulkanHierarchyPasses(VulkanPasses& gpu) {
  return std::make_unique<VulkanHierarchy>(gpu);
}

}  // namespace rayspace::gpu_backend
