// The emulator as a backend: each method calls the pass function that mirrors its kernel.
#include "rayspace/emu/backend.h"

#include "rayspace/error.h"
#include "rayspace/parallel.h"

namespace rayspace::emu {
namespace {

std::uint32_t Morton2(std::uint32_t x, std::uint32_t y) {
  std::uint32_t m = 0;
  for (int b = 15; b >= 0; --b) m = (m << 2) | (((y >> b) & 1u) << 1) | ((x >> b) & 1u);
  return m;
}

class EmuFrame final : public FramePasses {
 public:
  std::string Name() const override { return "emu"; }
  GBuffer Raster(const gpu::FrameConstants& fc, const SceneBuffers& scene) override { return PassRaster(fc, scene); }
  std::vector<gpu::Surface> SurfacesFromGBuffer(const gpu::FrameConstants& fc, const GBuffer& g,
                                                const SceneBuffers& scene) override {
    return PassSurfacesFromGBuffer(fc, g, scene);
  }
  std::vector<gpu::Surface> SurfacesFromHits(const std::vector<gpu::Ray>& rays, const std::vector<std::uint64_t>& hits,
                                             const SceneBuffers& scene) override {
    return PassSurfacesFromHits(rays, hits, scene);
  }
  SparseRays Raygen(std::uint32_t kind, const gpu::FrameConstants& fc, const std::vector<gpu::Surface>& surfaces,
                    const SceneBuffers& scene) override {
    switch (kind) {
      case gpu::kRayShadow: return PassRaygenShadow(fc, surfaces, scene);
      case gpu::kRayReflection: return PassRaygenReflection(fc, surfaces, scene);
      case gpu::kRayRefraction: return PassRaygenRefraction(fc, surfaces, scene);
    }
    RS_CHECK_MSG(false, "unknown ray kind {}", kind);
    return {};
  }
  Trimmed Trim(std::uint32_t, const SparseRays& sparse) override { return PassTrim(sparse); }
  void Shade(const gpu::FrameConstants& fc, const std::vector<gpu::Surface>& surfaces,
             const std::vector<std::uint32_t>& shadow_flags, const std::vector<std::uint32_t>& shadow_offsets,
             const std::vector<std::uint32_t>& occluded, const SceneBuffers& scene,
             std::vector<std::uint64_t>& accum) override {
    PassShade(fc, surfaces, shadow_flags, shadow_offsets, occluded, scene, accum);
  }
  std::vector<std::uint8_t> Resolve(const gpu::FrameConstants& fc, const std::vector<std::uint64_t>& accum) override {
    return PassResolve(fc, accum);
  }
};

class EmuHierarchy final : public HierarchyPasses {
 public:
  std::string Name() const override { return "emu"; }
  std::vector<std::uint32_t> Hash(const std::vector<gpu::Ray>& rays, const SceneBuffers& scene, const HashConfig& h,
                                  std::uint32_t quadtree_width, int quadtree_depth) override {
    return quadtree_width ? PassHashQuadtree(rays, quadtree_width, quadtree_depth) : PassHash(rays, scene, h);
  }
  Chunks Compress(const std::vector<std::uint32_t>& keys) override { return PassCompress(keys); }
  std::vector<std::uint32_t> SortChunks(const std::vector<std::uint32_t>& chunk_keys) override {
    return PassSortChunks(chunk_keys);
  }
  std::vector<std::uint32_t> Decompress(const Chunks& chunks, const std::vector<std::uint32_t>& sorted) override {
    return PassDecompress(chunks, sorted);
  }
  std::vector<gpu::ConeNode> BuildLeaves(const std::vector<gpu::Ray>& rays, const std::vector<std::uint32_t>& order,
                                         const std::vector<std::uint32_t>& first) override {
    return PassBuildLeaves(rays, order, first);
  }
  std::vector<gpu::ConeNode> BuildParents(const std::vector<gpu::ConeNode>& below,
                                          const std::vector<std::uint32_t>& first) override {
    return PassBuildParents(below, first);
  }
  std::vector<std::uint8_t> ObjectMask(const std::vector<gpu::ConeNode>& top, const std::vector<glm::vec4>& object_spheres,
                                       float eps) override {
    return PassObjectMask(top, object_spheres, eps);
  }
  PairSlots TraverseTop(const std::vector<gpu::ConeNode>& top, std::uint32_t t0, std::uint32_t t1, std::uint32_t b0,
                        std::uint32_t b1, const std::vector<glm::vec4>& tri_spheres, const SceneBuffers& scene,
                        const std::vector<std::uint8_t>& object_mask, float eps) override {
    return PassTraverseTop(top, t0, t1, b0, b1, tri_spheres, scene, object_mask, eps);
  }
  PairSlots TraverseLevel(const std::vector<std::uint32_t>& pairs, const std::vector<gpu::ConeNode>& nodes,
                          const std::vector<std::uint32_t>& first, std::uint32_t base_up, std::uint32_t base,
                          std::uint32_t children_max, std::uint32_t b0, const std::vector<glm::vec4>& tri_spheres,
                          float eps) override {
    return PassTraverseLevel(pairs, nodes, first, base_up, base, children_max, b0, tri_spheres, eps);
  }
  std::vector<std::uint32_t> Reduce(Reduction reduction, int component, const std::vector<std::uint8_t>& flags,
                                    const std::vector<std::uint32_t>& values) override {
    return reduction == Reduction::kHierarchical ? ReduceHierarchical(flags, values, component) : ReduceScan(flags, values);
  }
  std::vector<std::uint32_t> Intersect(const std::vector<std::uint32_t>& pairs, const std::vector<std::uint32_t>& first1,
                                       std::uint32_t base1, std::uint32_t b0, const std::vector<std::uint32_t>& order,
                                       const std::vector<gpu::Ray>& rays, const SceneBuffers& scene,
                                       std::vector<std::uint64_t>* hits, std::vector<std::uint32_t>* occluded) override {
    return PassIntersect(pairs, first1, base1, b0, order, rays, scene, hits, occluded);
  }
};

}  // namespace

ForwardingHierarchyPasses::ForwardingHierarchyPasses(HierarchyPasses* target)
    : t_(target ? *target : EmuHierarchyPasses()) {}

std::string ForwardingHierarchyPasses::Name() const { return t_.Name(); }

FramePasses& EmuFramePasses() {
  static EmuFrame f;
  return f;
}

HierarchyPasses& EmuHierarchyPasses() {
  static EmuHierarchy h;
  return h;
}

std::vector<std::uint32_t> PassHashQuadtree(const std::vector<gpu::Ray>& rays, std::uint32_t width, int depth) {
  std::vector<std::uint32_t> k(rays.size());
  const std::uint32_t w = std::max(width, 1u);
  ParallelFor(rays.size(), [&](std::size_t i) {
    const std::uint32_t px = rays[i].info.x % w, py = rays[i].info.x / w;
    const std::uint32_t light = rays[i].info.z == gpu::kRayShadow ? rays[i].info.w : 0u;
    k[i] = (light << (2 * depth)) | Morton2(px, py);
  });
  return k;
}

}  // namespace rayspace::emu
