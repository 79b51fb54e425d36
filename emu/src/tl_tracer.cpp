// The traversal lists as a frame's tracer (rayspace/emu/tl/tracer.h).
#include "rayspace/emu/tl/tracer.h"

#include <algorithm>
#include <chrono>
#include <cstring>

#include <nlohmann/json.hpp>

#include "rayspace/emu/intersect.h"
#include "rayspace/emu/light_sample.h"
#include "rayspace/emu/tl/heads.h"
#include "rayspace/emu/output_checks.h"
#include "rayspace/error.h"

namespace rayspace::emu {
namespace {

class Tl final : public TlTracer {
 public:
  Tl(const SceneBuffers& scene, const tl::Options& options, HierarchyPasses& passes)
      : scene_(scene),
        options_(options),
        checked_(&passes != &EmuHierarchyPasses() ? CheckedHierarchyPasses(passes) : nullptr),
        passes_(checked_ ? *checked_ : passes) {
    RS_CHECK_MSG(tl::ValidListCount(options.lists), "traversal lists: {} lists (1, 2, 6 or 8)", options.lists);
  }

  std::string Name() const override { return "tl"; }
  void Describe(nlohmann::json& out) const override {
    out["algorithm"] = "tl";
    out["lists"] = options_.lists;
    out["node_order"] = options_.order == tl::Order::kEarliestFirst ? "earliest-first" : "latest-last";
    out["tree_big_fraction"] = options_.tree.big_fraction;
    out["tree_leaf_triangles"] = options_.tree.leaf_triangles;
    out["backface_culling"] = options_.cull;
    out["frustum_culling"] = options_.cells;
    out["polygon_heads"] = options_.heads == layout::kTlHeadsRegular ? "regular" : options_.heads == layout::kTlHeadsSimple ? "simple" : "off";
    out["triangles"] = options_.cull ? "one-sided: met only from the front, (v1 - v0) x (v2 - v0)" : "two-sided";
    const TlShape s = Shape();
    out["tree_nodes"] = s.nodes;
    out["tree_elements"] = s.nodes + s.triangle_refs;
    out["list_elements"] = s.list_elements;
    out["list_culled_triangles"] = s.list_culled;
    out["list_bytes"] = s.bytes;
    out["backend"] = passes_.Name();
  }
  void BeginBatch(const BatchContext& ctx) override { ctx_ = ctx; }
  const std::vector<TlBatchStats>& Stats() const override { return stats_; }
  TlShape Shape() const override {
    TlShape s{options_.lists, static_cast<std::uint32_t>(tree_.links.size()), static_cast<std::uint32_t>(tree_.triangles.size()),
              built_ ? lists_.Bytes() : 0, options_.cull, options_.heads, windows_.windows.size() * sizeof(std::uint32_t), {}, {}};
    if (!built_) return s;
    for (std::uint32_t k = 0; k < options_.lists; ++k) {
      s.list_elements.push_back(lists_.first[k + 1] - lists_.first[k]);
      std::uint32_t refs = 0;
      for (std::uint32_t i = lists_.first[k]; i < lists_.first[k + 1]; ++i) refs += tl::IsTriangle(static_cast<tl::Escape>(lists_.escapes[i]));
      s.list_culled.push_back(s.triangle_refs - refs);
    }
    return s;
  }

  void Closest(const std::vector<layout::Ray>& rays, std::vector<std::uint64_t>& hits) override {
    TlWalks w = Trace(rays, 0);
    hits = std::move(w.hits);
  }
  void Occluded(const std::vector<layout::Ray>& rays, std::vector<std::uint32_t>& occluded) override {
    TlWalks w = Trace(rays, 1);
    occluded = std::move(w.occluded);
  }

 private:
  TlWalks Trace(const std::vector<layout::Ray>& rays, std::uint32_t shadow) {
    if (!built_) BuildLists();
    const std::string label = "tl.trace." + ctx_.name;
    // Eye rays walk their cell's window (tl.cells, again whenever the frame's camera or size
    // changes), the others their triangle's.
    const bool cells = options_.cells && ctx_.kind == layout::kRayPrimary && ctx_.frame;
    if (cells && (cells_.windows.empty() || std::memcmp(&cells_frame_, ctx_.frame, sizeof cells_frame_) != 0)) {
      cells_frame_ = *ctx_.frame;
      BuildCells(cells_frame_);
    }
    passes_.Label(label);
    const auto t0 = std::chrono::steady_clock::now();
    TlWalks w = passes_.TlTrace({.first = lists_.first,
                                 .escapes = lists_.escapes,
                                 .words = lists_.words,
                                 .vertices = lists_.vertices,
                                 .rays = rays,
                                 .shadow = shadow,
                                 .cull = options_.cull ? 1u : 0u,
                                 .heads = cells ? layout::kTlHeadsCells : options_.heads,
                                 // read only by the per-polygon heads' case of a ray
                                 .tri_words = !cells && options_.heads != layout::kTlHeadsOff ? std::span<const tl::Word>(tree_.tri_words)
                                                                                               : std::span<const tl::Word>(),
                                 .windows = cells ? cells_.windows : windows_.windows});
    RecordSince(label, t0, rays.size());
    if (ctx_.digest) {
      if (shadow)
        ctx_.digest->Add(label, "occluded", w.occluded);
      else
        ctx_.digest->Add(label, "hits", w.hits);
      ctx_.digest->Add(label, "spheres", w.spheres);
      ctx_.digest->Add(label, "triangles", w.triangles);
    }
    const auto tc = std::chrono::steady_clock::now();
    Count(rays, w);
    RecordSince("tl.statistics." + ctx_.name, tc, rays.size());
    return w;
  }
  // One of the batch's timed steps, from t0 to now, for --timings.
  void RecordSince(const std::string& name, std::chrono::steady_clock::time_point t0, std::size_t elements) {
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    if (ctx_.subpasses) ctx_.subpasses->push_back({name, ms, elements});
  }
  // The tree depends on the scene alone (built once, as the other tracers' hierarchies are); the
  // lists are the frame's pass "tl.lists", run before the first batch that needs them, so a frame
  // with nothing to trace builds none.
  void BuildLists() {
    if (tree_.links.empty() && tree_.tri_words.empty()) {
      // The scene's tree, built on the host: timed as its own step, so --timings names it.
      const auto tt = std::chrono::steady_clock::now();
      tree_ = tl::PrepareTree(scene_.triangles, options_.tree);
      RecordSince("tl.tree", tt, scene_.triangles.size());
    }
    directions_ = tl::Directions(options_.lists);
    passes_.Label("tl.lists");
    const auto t0 = std::chrono::steady_clock::now();
    TlListArrays a = passes_.TlLists({.tree = tree_.View(),
                                      .directions = directions_,
                                      .order = static_cast<std::uint32_t>(options_.order),
                                      .cull = options_.cull ? 1u : 0u});
    const std::vector<std::uint32_t> lengths = a.lengths;
    lists_ = tl::Assemble(tree_, options_.lists, std::move(a), options_.cull);
    built_ = true;
    RecordSince("tl.lists", t0, lists_.escapes.size());
    if (ctx_.digest) {
      ctx_.digest->Add("tl.lists", "escapes", lists_.escapes);
      ctx_.digest->Add("tl.lists", "words", lists_.words);
      ctx_.digest->Add("tl.lists", "lengths", lengths);
    }
    if (options_.heads != layout::kTlHeadsOff) BuildWindows();
  }
  // Where shadow rays may start: the corners of every light's samples.
  void AddLightCorners(std::vector<glm::vec3>& points) const {
    for (const layout::Light& l : scene_.lights) {
      glm::vec3 lo, hi;
      LightCorners(l, lo, hi);
      points.push_back(lo);
      points.push_back(hi);
    }
  }
  // Per-cell heads of the eye rays: the pass "tl.cells", before the first primary batch.
  void BuildCells(const layout::FrameConstants& fc) {
    std::vector<glm::vec3> points{Xyz(fc.eye)};
    AddLightCorners(points);
    cells_ = WindowsPass("tl.cells", [&] {
      return passes_.TlCells({.first = lists_.first,
                              .escapes = lists_.escapes,
                              .words = lists_.words,
                              .vertices = lists_.vertices,
                              .frame = fc,
                              .margin = tl::HeadsMargin(scene_.lo, scene_.hi, points)});
    });
  }
  // Per-polygon heads: the pass "tl.heads" right after the lists.
  void BuildWindows() {
    std::vector<glm::vec3> lights;
    AddLightCorners(lights);
    windows_ = WindowsPass("tl.heads", [&] {
      return passes_.TlHeads({.first = lists_.first,
                              .escapes = lists_.escapes,
                              .words = lists_.words,
                              .vertices = lists_.vertices,
                              .tri_words = tree_.tri_words,
                              .mode = options_.heads,
                              .margin = tl::HeadsMargin(scene_.lo, scene_.hi, lights)});
    });
  }
  // A pass that writes windows, labelled, timed among the batch's subpasses and digested.
  template <typename F>
  TlWindows WindowsPass(const char* name, F&& run) {
    passes_.Label(name);
    const auto t0 = std::chrono::steady_clock::now();
    TlWindows w = run();
    RecordSince(name, t0, w.windows.size() / 2);
    if (ctx_.digest) ctx_.digest->Add(name, "windows", w.windows);
    return w;
  }
  void Count(const std::vector<layout::Ray>& rays, const TlWalks& w) {
    TlBatchStats s;
    s.name = ctx_.name;
    s.kind = ctx_.kind;
    s.rays = rays.size();
    s.list_rays.assign(options_.lists, 0);
    s.list_spheres.assign(options_.lists, 0);
    s.list_triangles.assign(options_.lists, 0);
    for (std::size_t i = 0; i < rays.size(); ++i) {
      const std::uint32_t k = tl::ListFor(options_.lists, Xyz(rays[i].direction_tmax));
      ++s.list_rays[k];
      s.list_spheres[k] += w.spheres[i];
      s.list_triangles[k] += w.triangles[i];
      s.spheres += w.spheres[i];
      s.triangles += w.triangles[i];
    }
    s.warp_steps = WarpSteps(w.spheres, w.triangles);
    s.has_entries = w.entries.size() == rays.size();
    for (const std::uint32_t x : w.entries) s.entries += x;
    stats_.push_back(std::move(s));
  }

  const SceneBuffers& scene_;
  tl::Options options_;
  std::unique_ptr<HierarchyPasses> checked_;  // a backend's outputs checked (emu/output_checks.h)
  HierarchyPasses& passes_;
  tl::Tree tree_;
  std::vector<glm::vec4> directions_;
  tl::Lists lists_;
  TlWindows windows_;  // per-polygon heads (empty when off)
  TlWindows cells_;    // per-cell heads of the eye rays (empty until the first primary batch)
  layout::FrameConstants cells_frame_{};  // the frame cells_ was built for
  bool built_ = false;
  BatchContext ctx_;
  std::vector<TlBatchStats> stats_;
};

}  // namespace

std::uint64_t WarpSteps(std::span<const std::uint32_t> spheres, std::span<const std::uint32_t> triangles) {
  RS_CHECK(spheres.size() == triangles.size());
  std::uint64_t steps = 0;
  for (std::size_t b = 0; b < spheres.size(); b += kTlWarpRays) {
    const std::size_t e = std::min(spheres.size(), b + kTlWarpRays);
    std::uint64_t longest = 0;
    for (std::size_t i = b; i < e; ++i) longest = std::max<std::uint64_t>(longest, std::uint64_t{spheres[i]} + triangles[i]);
    steps += longest * (e - b);
  }
  return steps;
}

std::unique_ptr<TlTracer> MakeTlTracer(const SceneBuffers& scene, const tl::Options& options, HierarchyPasses* passes) {
  return std::make_unique<Tl>(scene, options, passes ? *passes : EmuHierarchyPasses());
}

}  // namespace rayspace::emu
