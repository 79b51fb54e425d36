#include "rayspace/verify/pass_table.h"

#include <bit>

#include <fmt/format.h>

#include "rayspace/emu/frame.h"
#include "rayspace/error.h"
#include "rayspace/pass_registry.h"

namespace rayspace::verify {
namespace {

using U32 = std::vector<std::uint32_t>;

float Eps(const BufferSet& in) { return std::bit_cast<float>(in.U32("eps_bits")); }

emu::GBuffer GetGBuffer(const BufferSet& in) {
  emu::GBuffer g;
  g.width = static_cast<int>(in.U32("width"));
  g.height = static_cast<int>(in.U32("height"));
  g.position = in.Get<glm::vec4>("position");
  g.normal = in.Get<glm::vec4>("normal");
  g.prim = in.Get<std::uint32_t>("prim");
  const std::size_t n = static_cast<std::size_t>(g.width) * g.height;
  if (g.position.size() != n || g.normal.size() != n || g.prim.size() != n)
    ThrowInput("G-buffer inputs hold {}/{}/{} pixels, expected {}", g.position.size(), g.normal.size(), g.prim.size(), n);
  return g;
}

emu::Chunks GetChunks(const BufferSet& in) {
  return {in.Get<std::uint32_t>("chunk_key"), in.Get<std::uint32_t>("chunk_base"), in.Get<std::uint32_t>("chunk_size")};
}

std::uint32_t Kind(const BufferSet& in) {
  const std::uint32_t k = in.U32("kind");
  if (k > gpu::kRayRefraction) ThrowInput("scalar 'kind' = {} is not a ray kind", k);
  return k;
}

// Indices a pass reads must be in range, or the emulator itself would read out of bounds.
void CheckIndices(const char* what, const U32& v, std::size_t bound) {
  for (std::size_t i = 0; i < v.size(); ++i)
    if (v[i] >= bound) ThrowInput("input '{}' element {} is {}, out of range [0, {})", what, i, v[i], bound);
}
void CheckFirst(const U32& first, std::size_t items) {
  if (first.empty() || first.front() != 0 || first.back() != items)
    ThrowInput("input 'first' must run from 0 to {}", items);
  for (std::size_t i = 1; i < first.size(); ++i)
    if (first[i] < first[i - 1]) ThrowInput("input 'first' decreases at {}", i);
}

BufferSet Slots(const emu::PairSlots& s) {
  BufferSet out;
  out.Put("flags", s.flags);
  out.Put("values", s.values);
  out.Put("tested", s.tested);
  return out;
}

std::vector<PassMethod> Build() {
  std::vector<PassMethod> m;
  // The registry names each call's pass and its index outputs; the table adds how to run it.
  auto add = [&m](const char* call, std::function<BufferSet(const BufferSet&, Backends&)> run) {
    PassMethod pm;
    pm.method = call;
    std::vector<std::string> owners;  // the passes that list the call, in registry order
    for (const PassSpec& p : kPasses)
      for (const CallSpec& c : p.calls)
        if (c.name == call) {
          owners.emplace_back(p.name);
          for (std::string_view b : c.index_outputs) pm.index_outputs.insert(std::string(b));
        }
    RS_CHECK_MSG(!owners.empty(), "pass table: call '{}' is not in the pass registry", call);
    if (owners.size() == 1)
      pm.pass = [name = owners[0]](const BufferSet&) { return name; };
    else  // the call's ray kind selects the pass (rayspace/pass_registry.h lists them in kind order)
      pm.pass = [owners](const BufferSet& in) {
        const std::uint32_t k = Kind(in);
        if (k >= owners.size()) ThrowInput("scalar 'kind' = {} selects none of {} passes", k, owners.size());
        return owners[k];
      };
    pm.run = std::move(run);
    m.push_back(std::move(pm));
  };
  add("raster", [](const BufferSet& in, Backends& b) {
                 const emu::GBuffer g = b.frame.Raster(in.GetOne<gpu::FrameConstants>("frame"), in.GetScene());
                 BufferSet out;
                 out.Put("diffuse", g.diffuse);
                 out.Put("specular", g.specular);
                 out.Put("position", g.position);
                 out.Put("normal", g.normal);
                 out.Put("prim", g.prim);
                 out.Put("depth", g.depth);
                 return out;
               });
  add("surfaces", [](const BufferSet& in, Backends& b) {
                 const SceneBuffers scene = in.GetScene();
                 const emu::GBuffer g = GetGBuffer(in);
                 for (std::uint32_t p : g.prim)
                   if (p != gpu::kNoPrim && p >= scene.triangles.size()) ThrowInput("input 'prim' names triangle {}", p);
                 BufferSet out;
                 out.Put("surfaces", b.frame.SurfacesFromGBuffer(in.GetOne<gpu::FrameConstants>("frame"), g, scene));
                 return out;
               });
  add("surfaces.hits", [](const BufferSet& in, Backends& b) {
                 const SceneBuffers scene = in.GetScene();
                 const auto rays = in.Get<gpu::Ray>("rays");
                 const auto hits = in.Get<std::uint64_t>("hits");
                 if (hits.size() != rays.size()) ThrowInput("inputs 'rays' and 'hits' differ in length");
                 for (std::uint64_t h : hits)
                   if (h != ~std::uint64_t{0} && static_cast<std::uint32_t>(h) >= scene.triangles.size())
                     ThrowInput("input 'hits' names triangle {}", static_cast<std::uint32_t>(h));
                 BufferSet out;
                 out.Put("surfaces", b.frame.SurfacesFromHits(rays, hits, scene));
                 return out;
               });
  add("raygen", [](const BufferSet& in, Backends& b) {
                 const emu::SparseRays r = b.frame.Raygen(Kind(in), in.GetOne<gpu::FrameConstants>("frame"),
                                                          in.Get<gpu::Surface>("surfaces"), in.GetScene());
                 BufferSet out;
                 out.Put("rays", r.rays);
                 out.Put("flags", r.flags);
                 return out;
               });
  add("trim", [](const BufferSet& in, Backends& b) {
                 const emu::SparseRays s{in.Get<gpu::Ray>("rays"), in.Get<std::uint32_t>("flags")};
                 if (s.rays.size() != s.flags.size()) ThrowInput("inputs 'rays' and 'flags' differ in length");
                 const emu::Trimmed t = b.frame.Trim(Kind(in), s);
                 BufferSet out;
                 out.Put("rays", t.rays);
                 out.Put("offsets", t.offsets);
                 return out;
               });
  add("shade", [](const BufferSet& in, Backends& b) {
                 const SceneBuffers scene = in.GetScene();
                 const auto surfaces = in.Get<gpu::Surface>("surfaces");
                 const auto flags = in.Get<std::uint32_t>("shadow_flags"), offsets = in.Get<std::uint32_t>("shadow_offsets"),
                            occluded = in.Get<std::uint32_t>("occluded");
                 auto accum = in.Get<std::uint64_t>("accum");
                 const gpu::FrameConstants fc = in.GetOne<gpu::FrameConstants>("frame");
                 if (accum.size() != static_cast<std::size_t>(fc.dims.x) * fc.dims.y * 3) ThrowInput("input 'accum' does not match the frame size");
                 if (!scene.lights.empty()) {
                   if (flags.size() != surfaces.size() * scene.lights.size() || offsets.size() != flags.size())
                     ThrowInput("inputs 'shadow_flags'/'shadow_offsets' do not hold surfaces x lights slots");
                   for (std::size_t i = 0; i < flags.size(); ++i)
                     if (flags[i] && offsets[i] >= occluded.size()) ThrowInput("input 'shadow_offsets' element {} is out of range", i);
                 }
                 for (const gpu::Surface& s : surfaces)
                   if (s.info.y >= fc.dims.x * fc.dims.y || (s.info.x != gpu::kNoPrim && s.info.z >= scene.materials.size()))
                     ThrowInput("input 'surfaces' names a pixel or material out of range");
                 b.frame.Shade(fc, surfaces, flags, offsets, occluded, scene, accum);
                 BufferSet out;
                 out.Put("accum", accum);
                 return out;
               });
  add("resolve", [](const BufferSet& in, Backends& b) {
                 const gpu::FrameConstants fc = in.GetOne<gpu::FrameConstants>("frame");
                 const auto accum = in.Get<std::uint64_t>("accum");
                 if (accum.size() != static_cast<std::size_t>(fc.dims.x) * fc.dims.y * 3) ThrowInput("input 'accum' does not match the frame size");
                 BufferSet out;
                 out.Put("rgb", b.frame.Resolve(fc, accum));
                 return out;
               });
  add("hash", [](const BufferSet& in, Backends& b) {
                 emu::HashConfig h;
                 h.light_bits = static_cast<int>(in.U32("light_bits"));
                 h.polar_bits = static_cast<int>(in.U32("polar_bits"));
                 h.azimuth_bits = static_cast<int>(in.U32("azimuth_bits"));
                 h.origin_bits = static_cast<int>(in.U32("origin_bits"));
                 h.direction_bits = static_cast<int>(in.U32("direction_bits"));
                 BufferSet out;
                 out.Put("keys", b.hierarchy.Hash(in.Get<gpu::Ray>("rays"), in.GetScene(), h, in.U32("quadtree_width"),
                                                  static_cast<int>(in.U32("quadtree_depth"))));
                 return out;
               });
  add("compress", [](const BufferSet& in, Backends& b) {
                 const emu::Chunks c = b.hierarchy.Compress(in.Get<std::uint32_t>("keys"));
                 BufferSet out;
                 out.Put("chunk_key", c.key);
                 out.Put("chunk_base", c.base);
                 out.Put("chunk_size", c.size);
                 return out;
               });
  add("sort", [](const BufferSet& in, Backends& b) {
                 BufferSet out;
                 out.Put("chunk_order", b.hierarchy.SortChunks(in.Get<std::uint32_t>("chunk_key")));
                 return out;
               });
  add("decompress", [](const BufferSet& in, Backends& b) {
                 const emu::Chunks c = GetChunks(in);
                 const U32 sorted = in.Get<std::uint32_t>("chunk_order");
                 if (c.base.size() != c.key.size() || c.size.size() != c.key.size() || sorted.size() != c.key.size())
                   ThrowInput("chunk inputs differ in length");
                 CheckIndices("chunk_order", sorted, c.key.size());
                 BufferSet out;
                 out.Put("ray_order", b.hierarchy.Decompress(c, sorted));
                 return out;
               });
  add("build.leaves", [](const BufferSet& in, Backends& b) {
                 const auto rays = in.Get<gpu::Ray>("rays");
                 const U32 order = in.Get<std::uint32_t>("order"), first = in.Get<std::uint32_t>("first");
                 CheckIndices("order", order, rays.size());
                 CheckFirst(first, order.size());
                 BufferSet out;
                 out.Put("nodes", b.hierarchy.BuildLeaves(rays, order, first));
                 return out;
               });
  add("build.parents", [](const BufferSet& in, Backends& b) {
                 const auto below = in.Get<gpu::ConeNode>("below");
                 const U32 first = in.Get<std::uint32_t>("first");
                 CheckFirst(first, below.size());
                 BufferSet out;
                 out.Put("nodes", b.hierarchy.BuildParents(below, first));
                 return out;
               });
  add("traverse.objects", [](const BufferSet& in, Backends& b) {
                 BufferSet out;
                 out.Put("mask", b.hierarchy.ObjectMask(in.Get<gpu::ConeNode>("top"), in.Get<glm::vec4>("object_spheres"), Eps(in)));
                 return out;
               });
  add("traverse.top", [](const BufferSet& in, Backends& b) {
                 const SceneBuffers scene = in.GetScene();
                 const auto top = in.Get<gpu::ConeNode>("top");
                 const auto spheres = in.Get<glm::vec4>("tri_spheres");
                 const auto mask = in.Get<std::uint8_t>("object_mask");
                 const std::uint32_t t0 = in.U32("t0"), t1 = in.U32("t1"), b0 = in.U32("b0"), b1 = in.U32("b1");
                 if (t0 > t1 || t1 > top.size() || b0 > b1 || b1 > scene.triangles.size() || spheres.size() != scene.triangles.size() ||
                     (!mask.empty() && mask.size() != top.size() * scene.objects.size()))
                   ThrowInput("traverse.top inputs out of range");
                 return Slots(b.hierarchy.TraverseTop(top, t0, t1, b0, b1, spheres, scene, mask, Eps(in)));
               });
  add("traverse.level", [](const BufferSet& in, Backends& b) {
                 const auto nodes = in.Get<gpu::ConeNode>("nodes");
                 const U32 pairs = in.Get<std::uint32_t>("pairs"), first = in.Get<std::uint32_t>("first");
                 const auto spheres = in.Get<glm::vec4>("tri_spheres");
                 const std::uint32_t base_up = in.U32("base_up"), cmax = in.U32("children_max"), b0 = in.U32("b0");
                 CheckFirst(first, nodes.size());
                 for (std::uint32_t p : pairs) {
                   const std::uint32_t parent = base_up + (p >> emu::kPairTriangleBits);
                   if (parent + 1 >= first.size() || b0 + (p & emu::kPairTriangleMask) >= spheres.size() ||
                       first[parent + 1] - first[parent] > cmax)
                     ThrowInput("input 'pairs' holds {} out of range", p);
                 }
                 return Slots(b.hierarchy.TraverseLevel(pairs, nodes, first, base_up, in.U32("base"), cmax, b0, spheres, Eps(in)));
               });
  add("reduce", [](const BufferSet& in, Backends& b) {
                 const auto flags = in.Get<std::uint8_t>("flags");
                 const U32 values = in.Get<std::uint32_t>("values");
                 const std::uint32_t s = in.U32("component");
                 if (flags.size() != values.size() || s == 0) ThrowInput("reduce inputs: flags/values differ or component is 0");
                 BufferSet out;
                 out.Put("pairs", b.hierarchy.Reduce(in.U32("scan") ? emu::Reduction::kScan : emu::Reduction::kHierarchical,
                                                     static_cast<int>(s), flags, values));
                 return out;
               });
  add("intersect", [](const BufferSet& in, Backends& b) {
                 const SceneBuffers scene = in.GetScene();
                 const U32 pairs = in.Get<std::uint32_t>("pairs"), first1 = in.Get<std::uint32_t>("first1"),
                           order = in.Get<std::uint32_t>("order");
                 const auto rays = in.Get<gpu::Ray>("rays");
                 const std::uint32_t base1 = in.U32("base1"), b0 = in.U32("b0");
                 CheckIndices("order", order, rays.size());
                 CheckFirst(first1, order.size());
                 for (std::uint32_t p : pairs)
                   if (base1 + (p >> emu::kPairTriangleBits) + 1 >= first1.size() ||
                       b0 + (p & emu::kPairTriangleMask) >= scene.triangles.size())
                     ThrowInput("input 'pairs' holds {} out of range", p);
                 const bool shadow = in.U32("shadow") != 0;
                 std::vector<std::uint64_t> hits;
                 U32 occluded;
                 if (shadow) occluded = in.Get<std::uint32_t>("occluded");
                 else hits = in.Get<std::uint64_t>("hits");
                 if ((shadow ? occluded.size() : hits.size()) != rays.size()) ThrowInput("intersect results differ in length from 'rays'");
                 BufferSet out;
                 out.Put("tests", b.hierarchy.Intersect(pairs, first1, base1, b0, order, rays, scene, shadow ? nullptr : &hits,
                                                        shadow ? &occluded : nullptr));
                 if (shadow) out.Put("occluded", occluded);
                 else out.Put("hits", hits);
                 return out;
               });
  return m;
}

}  // namespace

const std::vector<PassMethod>& PassMethods() {
  static const std::vector<PassMethod> kMethods = Build();
  return kMethods;
}

const PassMethod& FindPassMethod(const std::string& method) {
  std::string known;
  for (const PassMethod& m : PassMethods()) {
    if (m.method == method) return m;
    known += (known.empty() ? "" : ", ") + m.method;
  }
  ThrowInput("unknown pass method '{}'; known: {}", method, known);
}

}  // namespace rayspace::verify
