// The passes of a frame and of the ray-space hierarchy behind one interface per group, so the same
// frame runner and hierarchy tracer drive either the emulator or the Vulkan kernels, and the diff and
// replay tools run one pass on both with the same inputs.
//
// Lifecycle: a backend is created once per process (the Vulkan one owns its device), handed by
// reference to RenderFrame / MakeHierarchyTracer, and outlives them. Every method is a pure function
// of its arguments: it reads inputs, returns outputs, keeps no state between calls (beyond caches of
// immutable inputs). A backend that fails (a Vulkan error) throws BackendError naming the pass and the
// failed call.
#pragma once
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "rayspace/emu/hierarchy.h"
#include "rayspace/emu/passes.h"

namespace rayspace::emu {

class BackendError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class FramePasses {
 public:
  virtual ~FramePasses() = default;
  virtual std::string Name() const = 0;
  // The name of the frame pass about to run (e.g. "raygen.shadow.b0"), for reports.
  virtual void Label(const std::string& /*pass*/) {}
  virtual GBuffer Raster(const gpu::FrameConstants& fc, const SceneBuffers& scene) = 0;
  virtual std::vector<gpu::Surface> SurfacesFromGBuffer(const gpu::FrameConstants& fc, const GBuffer& g,
                                                        const SceneBuffers& scene) = 0;
  virtual std::vector<gpu::Surface> SurfacesFromHits(const std::vector<gpu::Ray>& rays,
                                                     const std::vector<std::uint64_t>& hits, const SceneBuffers& scene) = 0;
  virtual SparseRays Raygen(std::uint32_t kind, const gpu::FrameConstants& fc, const std::vector<gpu::Surface>& surfaces,
                            const SceneBuffers& scene) = 0;
  virtual Trimmed Trim(std::uint32_t kind, const SparseRays& sparse) = 0;
  virtual void Shade(const gpu::FrameConstants& fc, const std::vector<gpu::Surface>& surfaces,
                     const std::vector<std::uint32_t>& shadow_flags, const std::vector<std::uint32_t>& shadow_offsets,
                     const std::vector<std::uint32_t>& occluded, const SceneBuffers& scene,
                     std::vector<std::uint64_t>& accum) = 0;
  virtual std::vector<std::uint8_t> Resolve(const gpu::FrameConstants& fc, const std::vector<std::uint64_t>& accum) = 0;
};

class HierarchyPasses {
 public:
  virtual ~HierarchyPasses() = default;
  virtual std::string Name() const = 0;
  // The name of the tracer's sub-pass about to run (e.g. "traverse.L2.shadow.b0"), for reports.
  virtual void Label(const std::string& /*pass*/) {}
  // `quadtree_width` > 0: Roger's quadtree keys (light, Morton order of the pixel) instead of PassHash.
  virtual std::vector<std::uint32_t> Hash(const std::vector<gpu::Ray>& rays, const SceneBuffers& scene,
                                          const HashConfig& h, std::uint32_t quadtree_width, int quadtree_depth) = 0;
  virtual Chunks Compress(const std::vector<std::uint32_t>& keys) = 0;
  virtual std::vector<std::uint32_t> SortChunks(const std::vector<std::uint32_t>& chunk_keys) = 0;
  virtual std::vector<std::uint32_t> Decompress(const Chunks& chunks, const std::vector<std::uint32_t>& sorted) = 0;
  virtual std::vector<gpu::ConeNode> BuildLeaves(const std::vector<gpu::Ray>& rays, const std::vector<std::uint32_t>& order,
                                                 const std::vector<std::uint32_t>& first) = 0;
  virtual std::vector<gpu::ConeNode> BuildParents(const std::vector<gpu::ConeNode>& below,
                                                  const std::vector<std::uint32_t>& first) = 0;
  // CRSH: 1 where top node e / objects may meet object sphere e % objects.
  virtual std::vector<std::uint8_t> ObjectMask(const std::vector<gpu::ConeNode>& top,
                                               const std::vector<glm::vec4>& object_spheres, float eps) = 0;
  virtual PairSlots TraverseTop(const std::vector<gpu::ConeNode>& top, std::uint32_t t0, std::uint32_t t1, std::uint32_t b0,
                                std::uint32_t b1, const std::vector<glm::vec4>& tri_spheres, const SceneBuffers& scene,
                                const std::vector<std::uint8_t>& object_mask, float eps) = 0;
  virtual PairSlots TraverseLevel(const std::vector<std::uint32_t>& pairs, const std::vector<gpu::ConeNode>& nodes,
                                  const std::vector<std::uint32_t>& first, std::uint32_t base_up, std::uint32_t base,
                                  std::uint32_t children_max, std::uint32_t b0, const std::vector<glm::vec4>& tri_spheres,
                                  float eps) = 0;
  virtual std::vector<std::uint32_t> Reduce(Reduction reduction, int component, const std::vector<std::uint8_t>& flags,
                                            const std::vector<std::uint32_t>& values) = 0;
  // Hits / occluded must be sized to the rays and initialised (miss, 0); results are merged in.
  virtual std::vector<std::uint32_t> Intersect(const std::vector<std::uint32_t>& pairs, const std::vector<std::uint32_t>& first1,
                                               std::uint32_t base1, std::uint32_t b0, const std::vector<std::uint32_t>& order,
                                               const std::vector<gpu::Ray>& rays, const SceneBuffers& scene,
                                               std::vector<std::uint64_t>* hits, std::vector<std::uint32_t>* occluded) = 0;
};

// Forwards every pass to another backend (the emulator's by default): tools that change or observe
// one pass override just that one.
class ForwardingHierarchyPasses : public HierarchyPasses {
 public:
  explicit ForwardingHierarchyPasses(HierarchyPasses* target = nullptr);
  std::string Name() const override;
  void Label(const std::string& pass) override { t_.Label(pass); }
  std::vector<std::uint32_t> Hash(const std::vector<gpu::Ray>& rays, const SceneBuffers& scene, const HashConfig& h,
                                  std::uint32_t quadtree_width, int quadtree_depth) override {
    return t_.Hash(rays, scene, h, quadtree_width, quadtree_depth);
  }
  Chunks Compress(const std::vector<std::uint32_t>& keys) override { return t_.Compress(keys); }
  std::vector<std::uint32_t> SortChunks(const std::vector<std::uint32_t>& k) override { return t_.SortChunks(k); }
  std::vector<std::uint32_t> Decompress(const Chunks& c, const std::vector<std::uint32_t>& s) override { return t_.Decompress(c, s); }
  std::vector<gpu::ConeNode> BuildLeaves(const std::vector<gpu::Ray>& rays, const std::vector<std::uint32_t>& order,
                                         const std::vector<std::uint32_t>& first) override {
    return t_.BuildLeaves(rays, order, first);
  }
  std::vector<gpu::ConeNode> BuildParents(const std::vector<gpu::ConeNode>& below,
                                          const std::vector<std::uint32_t>& first) override {
    return t_.BuildParents(below, first);
  }
  std::vector<std::uint8_t> ObjectMask(const std::vector<gpu::ConeNode>& top, const std::vector<glm::vec4>& spheres,
                                       float eps) override {
    return t_.ObjectMask(top, spheres, eps);
  }
  PairSlots TraverseTop(const std::vector<gpu::ConeNode>& top, std::uint32_t t0, std::uint32_t t1, std::uint32_t b0,
                        std::uint32_t b1, const std::vector<glm::vec4>& tri_spheres, const SceneBuffers& scene,
                        const std::vector<std::uint8_t>& object_mask, float eps) override {
    return t_.TraverseTop(top, t0, t1, b0, b1, tri_spheres, scene, object_mask, eps);
  }
  PairSlots TraverseLevel(const std::vector<std::uint32_t>& pairs, const std::vector<gpu::ConeNode>& nodes,
                          const std::vector<std::uint32_t>& first, std::uint32_t base_up, std::uint32_t base,
                          std::uint32_t children_max, std::uint32_t b0, const std::vector<glm::vec4>& tri_spheres,
                          float eps) override {
    return t_.TraverseLevel(pairs, nodes, first, base_up, base, children_max, b0, tri_spheres, eps);
  }
  std::vector<std::uint32_t> Reduce(Reduction reduction, int component, const std::vector<std::uint8_t>& flags,
                                    const std::vector<std::uint32_t>& values) override {
    return t_.Reduce(reduction, component, flags, values);
  }
  std::vector<std::uint32_t> Intersect(const std::vector<std::uint32_t>& pairs, const std::vector<std::uint32_t>& first1,
                                       std::uint32_t base1, std::uint32_t b0, const std::vector<std::uint32_t>& order,
                                       const std::vector<gpu::Ray>& rays, const SceneBuffers& scene,
                                       std::vector<std::uint64_t>* hits, std::vector<std::uint32_t>* occluded) override {
    return t_.Intersect(pairs, first1, base1, b0, order, rays, scene, hits, occluded);
  }

 private:
  HierarchyPasses& t_;
};

// The emulator's passes (emu/passes.h, emu/hierarchy.h).
FramePasses& EmuFramePasses();
HierarchyPasses& EmuHierarchyPasses();

// Roger et al.'s quadtree key: light index above the Morton code of the pixel (2 * depth bits).
std::vector<std::uint32_t> PassHashQuadtree(const std::vector<gpu::Ray>& rays, std::uint32_t width, int depth);

}  // namespace rayspace::emu
