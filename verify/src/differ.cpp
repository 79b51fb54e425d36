#include "rayspace/verify/differ.h"

#include <bit>
#include <chrono>
#include <filesystem>
#include <fstream>

#include <fmt/format.h>

namespace rayspace::verify {
namespace {

template <typename F>
double TimeMs(F&& f) {
  const auto t0 = std::chrono::steady_clock::now();
  f();
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

std::string HitsChanged(Tracer& tracer, const std::vector<gpu::Ray>& expected, const std::vector<gpu::Ray>& actual,
                        bool shadow) {
  if (expected.size() != actual.size()) return "changed (ray counts differ)";
  std::size_t changed = 0;
  if (shadow) {
    std::vector<std::uint32_t> a, b;
    tracer.Occluded(expected, a);
    tracer.Occluded(actual, b);
    for (std::size_t i = 0; i < a.size(); ++i) changed += a[i] != b[i];
  } else {
    std::vector<std::uint64_t> a, b;
    tracer.Closest(expected, a);
    tracer.Closest(actual, b);
    for (std::size_t i = 0; i < a.size(); ++i) changed += a[i] != b[i];
  }
  return changed ? fmt::format("changed for {} rays", changed) : "unchanged";
}

std::string DirName(std::size_t seq, const std::string& label) {
  std::string s = fmt::format("{:04d}-", seq);
  for (char c : label) s += (std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '-') ? c : '_';
  return s;
}

// The frame's passes through the Differ.
class FrameDecorator final : public emu::FramePasses {
 public:
  explicit FrameDecorator(Differ& d) : d_(d) {}
  std::string Name() const override { return "diff"; }
  void Label(const std::string& pass) override { d_.SetLabel(pass); }
  emu::GBuffer Raster(const gpu::FrameConstants& fc, const SceneBuffers& scene) override {
    BufferSet in;
    in.PutOne("frame", fc);
    in.PutScene(scene);
    const BufferSet out = d_.Call("raster", in);
    emu::GBuffer g;
    g.width = static_cast<int>(fc.dims.x);
    g.height = static_cast<int>(fc.dims.y);
    g.diffuse = out.Get<glm::vec4>("diffuse");
    g.specular = out.Get<glm::vec4>("specular");
    g.position = out.Get<glm::vec4>("position");
    g.normal = out.Get<glm::vec4>("normal");
    g.prim = out.Get<std::uint32_t>("prim");
    g.depth = out.Get<float>("depth");
    return g;
  }
  std::vector<gpu::Surface> SurfacesFromGBuffer(const gpu::FrameConstants& fc, const emu::GBuffer& g,
                                                const SceneBuffers& scene) override {
    BufferSet in;
    in.PutOne("frame", fc);
    in.scalars["width"] = g.width;
    in.scalars["height"] = g.height;
    in.Put("position", g.position);
    in.Put("normal", g.normal);
    in.Put("prim", g.prim);
    in.PutScene(scene);
    return d_.Call("surfaces", in).Get<gpu::Surface>("surfaces");
  }
  std::vector<gpu::Surface> SurfacesFromHits(const std::vector<gpu::Ray>& rays, const std::vector<std::uint64_t>& hits,
                                             const SceneBuffers& scene) override {
    BufferSet in;
    in.Put("rays", rays);
    in.Put("hits", hits);
    in.PutScene(scene);
    return d_.Call("surfaces.hits", in).Get<gpu::Surface>("surfaces");
  }
  emu::SparseRays Raygen(std::uint32_t kind, const gpu::FrameConstants& fc, const std::vector<gpu::Surface>& surfaces,
                         const SceneBuffers& scene) override {
    BufferSet in;
    in.scalars["kind"] = kind;
    in.PutOne("frame", fc);
    in.Put("surfaces", surfaces);
    in.PutScene(scene);
    const BufferSet out = d_.Call("raygen", in);
    return {out.Get<gpu::Ray>("rays"), out.Get<std::uint32_t>("flags")};
  }
  emu::Trimmed Trim(std::uint32_t kind, const emu::SparseRays& sparse) override {
    BufferSet in;
    in.scalars["kind"] = kind;
    in.Put("rays", sparse.rays);
    in.Put("flags", sparse.flags);
    const BufferSet out = d_.Call("trim", in);
    return {out.Get<gpu::Ray>("rays"), out.Get<std::uint32_t>("offsets")};
  }
  void Shade(const gpu::FrameConstants& fc, const std::vector<gpu::Surface>& surfaces,
             const std::vector<std::uint32_t>& shadow_flags, const std::vector<std::uint32_t>& shadow_offsets,
             const std::vector<std::uint32_t>& occluded, const SceneBuffers& scene,
             std::vector<std::uint64_t>& accum) override {
    BufferSet in;
    in.PutOne("frame", fc);
    in.Put("surfaces", surfaces);
    in.Put("shadow_flags", shadow_flags);
    in.Put("shadow_offsets", shadow_offsets);
    in.Put("occluded", occluded);
    in.Put("accum", accum);
    in.PutScene(scene);
    accum = d_.Call("shade", in).Get<std::uint64_t>("accum");
  }
  std::vector<std::uint8_t> Resolve(const gpu::FrameConstants& fc, const std::vector<std::uint64_t>& accum) override {
    BufferSet in;
    in.PutOne("frame", fc);
    in.Put("accum", accum);
    return d_.Call("resolve", in).Get<std::uint8_t>("rgb");
  }

 private:
  Differ& d_;
};

class HierarchyDecorator final : public emu::HierarchyPasses {
 public:
  explicit HierarchyDecorator(Differ& d) : d_(d) {}
  std::string Name() const override { return "diff"; }
  void Label(const std::string& pass) override { d_.SetLabel(pass); }
  std::vector<std::uint32_t> Hash(const std::vector<gpu::Ray>& rays, const SceneBuffers& scene, const emu::HashConfig& h,
                                  std::uint32_t quadtree_width, int quadtree_depth) override {
    BufferSet in;
    in.Put("rays", rays);
    in.PutScene(scene);
    in.scalars = {{"light_bits", h.light_bits}, {"polar_bits", h.polar_bits}, {"azimuth_bits", h.azimuth_bits},
                  {"origin_bits", h.origin_bits}, {"direction_bits", h.direction_bits},
                  {"quadtree_width", quadtree_width}, {"quadtree_depth", quadtree_depth}};
    return d_.Call("hash", in).Get<std::uint32_t>("keys");
  }
  emu::Chunks Compress(const std::vector<std::uint32_t>& keys) override {
    BufferSet in;
    in.Put("keys", keys);
    const BufferSet out = d_.Call("compress", in);
    return {out.Get<std::uint32_t>("chunk_key"), out.Get<std::uint32_t>("chunk_base"), out.Get<std::uint32_t>("chunk_size")};
  }
  std::vector<std::uint32_t> SortChunks(const std::vector<std::uint32_t>& chunk_keys) override {
    BufferSet in;
    in.Put("chunk_key", chunk_keys);
    return d_.Call("sort", in).Get<std::uint32_t>("chunk_order");
  }
  std::vector<std::uint32_t> Decompress(const emu::Chunks& c, const std::vector<std::uint32_t>& sorted) override {
    BufferSet in;
    in.Put("chunk_key", c.key);
    in.Put("chunk_base", c.base);
    in.Put("chunk_size", c.size);
    in.Put("chunk_order", sorted);
    return d_.Call("decompress", in).Get<std::uint32_t>("ray_order");
  }
  std::vector<gpu::ConeNode> BuildLeaves(const std::vector<gpu::Ray>& rays, const std::vector<std::uint32_t>& order,
                                         const std::vector<std::uint32_t>& first) override {
    BufferSet in;
    in.Put("rays", rays);
    in.Put("order", order);
    in.Put("first", first);
    return d_.Call("build.leaves", in).Get<gpu::ConeNode>("nodes");
  }
  std::vector<gpu::ConeNode> BuildParents(const std::vector<gpu::ConeNode>& below,
                                          const std::vector<std::uint32_t>& first) override {
    BufferSet in;
    in.Put("below", below);
    in.Put("first", first);
    return d_.Call("build.parents", in).Get<gpu::ConeNode>("nodes");
  }
  std::vector<std::uint8_t> ObjectMask(const std::vector<gpu::ConeNode>& top, const std::vector<glm::vec4>& object_spheres,
                                       float eps) override {
    BufferSet in;
    in.Put("top", top);
    in.Put("object_spheres", object_spheres);
    in.scalars["eps_bits"] = std::bit_cast<std::uint32_t>(eps);
    return d_.Call("traverse.objects", in).Get<std::uint8_t>("mask");
  }
  emu::PairSlots TraverseTop(const std::vector<gpu::ConeNode>& top, std::uint32_t t0, std::uint32_t t1, std::uint32_t b0,
                             std::uint32_t b1, const std::vector<glm::vec4>& tri_spheres, const SceneBuffers& scene,
                             const std::vector<std::uint8_t>& object_mask, float eps) override {
    BufferSet in;
    in.Put("top", top);
    in.Put("tri_spheres", tri_spheres);
    in.Put("object_mask", object_mask);
    in.PutScene(scene);
    in.scalars = {{"t0", t0}, {"t1", t1}, {"b0", b0}, {"b1", b1}, {"eps_bits", std::bit_cast<std::uint32_t>(eps)}};
    return Slots(d_.Call("traverse.top", in));
  }
  emu::PairSlots TraverseLevel(const std::vector<std::uint32_t>& pairs, const std::vector<gpu::ConeNode>& nodes,
                               const std::vector<std::uint32_t>& first, std::uint32_t base_up, std::uint32_t base,
                               std::uint32_t children_max, std::uint32_t b0, const std::vector<glm::vec4>& tri_spheres,
                               float eps) override {
    BufferSet in;
    in.Put("pairs", pairs);
    in.Put("nodes", nodes);
    in.Put("first", first);
    in.Put("tri_spheres", tri_spheres);
    in.scalars = {{"base_up", base_up}, {"base", base}, {"children_max", children_max}, {"b0", b0},
                  {"eps_bits", std::bit_cast<std::uint32_t>(eps)}};
    return Slots(d_.Call("traverse.level", in));
  }
  std::vector<std::uint32_t> Reduce(emu::Reduction reduction, int component, const std::vector<std::uint8_t>& flags,
                                    const std::vector<std::uint32_t>& values) override {
    BufferSet in;
    in.Put("flags", flags);
    in.Put("values", values);
    in.scalars = {{"scan", reduction == emu::Reduction::kScan ? 1 : 0}, {"component", component}};
    return d_.Call("reduce", in).Get<std::uint32_t>("pairs");
  }
  std::vector<std::uint32_t> Intersect(const std::vector<std::uint32_t>& pairs, const std::vector<std::uint32_t>& first1,
                                       std::uint32_t base1, std::uint32_t b0, const std::vector<std::uint32_t>& order,
                                       const std::vector<gpu::Ray>& rays, const SceneBuffers& scene,
                                       std::vector<std::uint64_t>* hits, std::vector<std::uint32_t>* occluded) override {
    BufferSet in;
    in.Put("pairs", pairs);
    in.Put("first1", first1);
    in.Put("order", order);
    in.Put("rays", rays);
    in.PutScene(scene);
    in.scalars = {{"base1", base1}, {"b0", b0}, {"shadow", occluded ? 1 : 0}};
    if (occluded) in.Put("occluded", *occluded);
    else in.Put("hits", *hits);
    const BufferSet out = d_.Call("intersect", in);
    if (occluded) *occluded = out.Get<std::uint32_t>("occluded");
    else *hits = out.Get<std::uint64_t>("hits");
    return out.Get<std::uint32_t>("tests");
  }

 private:
  static emu::PairSlots Slots(const BufferSet& out) {
    return {out.Get<std::uint8_t>("flags"), out.Get<std::uint32_t>("values"), out.Get<std::uint8_t>("tested")};
  }
  Differ& d_;
};

}  // namespace

CallRecord RunAndCompare(const PassMethod& method, const BufferSet& in, Backends& expected, Backends& actual,
                         BufferSet& actual_out, Tracer* hit_tracer) {
  CallRecord r;
  r.method = method.method;
  r.pass = method.pass(in);
  BufferSet e;
  r.expected_ms = TimeMs([&] { e = method.run(in, expected); });
  try {
    r.actual_ms = TimeMs([&] { actual_out = method.run(in, actual); });
  } catch (const emu::BackendError& err) {
    r.error = err.what();
    r.equal = false;
    return r;
  }
  for (const auto& [name, blob] : e.blobs()) {
    auto it = actual_out.blobs().find(name);
    RS_CHECK_MSG(it != actual_out.blobs().end(), "pass method {} gave no '{}' on the actual backend", method.method, name);
    r.buffers.push_back(CompareBlobs(r.pass, name, blob, it->second));
    r.equal &= r.buffers.back().Equal();
  }
  // A diverged ray batch: would the hits change? (Trim's dense rays are what gets traced.)
  if (hit_tracer && method.method == "trim" && !r.equal) {
    r.hits = HitsChanged(*hit_tracer, e.Get<gpu::Ray>("rays"), actual_out.Get<gpu::Ray>("rays"),
                         in.U32("kind") == gpu::kRayShadow);
  }
  return r;
}

Differ::Differ(Backends expected, Backends actual, DiffOptions options)
    : expected_(expected), actual_(actual), options_(std::move(options)) {
  frame_ = std::make_unique<FrameDecorator>(*this);
  hierarchy_ = std::make_unique<HierarchyDecorator>(*this);
}

Differ::~Differ() = default;

emu::FramePasses& Differ::frame() { return *frame_; }
emu::HierarchyPasses& Differ::hierarchy() { return *hierarchy_; }

BufferSet Differ::Call(const std::string& method_name, const BufferSet& in) {
  const PassMethod& method = FindPassMethod(method_name);
  BufferSet actual_out;
  CallRecord r = RunAndCompare(method, in, expected_, actual_, actual_out, options_.hit_tracer);
  r.seq = calls_.size();
  r.label = label_.empty() ? method_name : label_;
  if (!options_.save_dir.empty()) {
    r.saved = (std::filesystem::path(options_.save_dir) / DirName(r.seq, r.label)).string();
    in.Save(r.saved, method_name);
    nlohmann::json cj = nlohmann::json::array();
    for (const BufferComparison& c : r.buffers) {
      nlohmann::json j;
      c.ToJson(j);
      cj.push_back(j);
    }
    std::ofstream f(std::filesystem::path(r.saved) / "comparison.json");
    f << nlohmann::json{{"pass", r.pass}, {"label", r.label}, {"inject", options_.inject}, {"equal", r.equal}, {"buffers", cj}}.dump(2) << "\n";
  }
  calls_.push_back(r);
  const CallRecord& rec = calls_.back();
  if (!rec.error.empty()) throw DiffStop(fmt::format("{} ({}): the actual backend failed: {}", rec.pass, rec.label, rec.error));
  for (const BufferComparison& c : rec.buffers)
    if (!c.Equal() && method.index_outputs.count(c.buffer))
      throw DiffStop(fmt::format("{} ({}): '{}' differs, and later passes index with it", rec.pass, rec.label, c.buffer));
  return actual_out;
}

}  // namespace rayspace::verify
