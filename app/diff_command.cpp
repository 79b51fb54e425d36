#include "diff_command.h"
#include "cli_util.h"

#include <chrono>
#include <cstdio>
#include <fstream>
#include <regex>

#include <nlohmann/json.hpp>

#include "rayspace/compare.h"
#include "rayspace/emu/frame.h"
#include "rayspace/emu/hierarchy.h"
#include "rayspace/emu/intersect.h"
#include "rayspace/error.h"
#include "rayspace/gpu/passes.h"
#include "rayspace/scene.h"

#include <fmt/format.h>

namespace rayspace::app {
namespace {

// Words of a Ray: origin_tmin, direction_tmax (floats), info (uints), weight (floats).
constexpr std::uint32_t kRayFloats = 0xF0FFu;
// Words of a Surface: position, normal, incoming, weight (floats), info (uints).
constexpr std::uint32_t kSurfaceFloats = 0xFFFFu;
// Words of a ConeNode: all floats.
constexpr std::uint32_t kNodeFloats = 0xFFFu;

std::string EmulationModel() {
  std::string m = "x86-64";
#if defined(__x86_64__)
  __builtin_cpu_init();
  if (__builtin_cpu_supports("avx512f")) m += " avx512f";
  else if (__builtin_cpu_supports("avx2")) m += " avx2";
  if (__builtin_cpu_supports("fma")) m += " fma";
#endif
  return m;
}


gpu_backend::Faults ParseInject(const std::string& spec) {
  gpu_backend::Faults f;
  if (spec.empty()) return f;
  const auto colon = spec.find(':');
  const std::string pass = spec.substr(0, colon);
  std::uint32_t fault = 1;
  if (colon != std::string::npos) {
    try {
      fault = static_cast<std::uint32_t>(std::stoul(spec.substr(colon + 1)));
    } catch (...) {
      ThrowInput("--inject '{}': the fault after ':' must be a number", spec);
    }
  }
  std::string known;
  for (const auto& [name, count] : gpu_backend::KernelPasses()) {
    known += (known.empty() ? "" : ", ") + fmt::format("{} (faults 1..{})", name, count);
    if (name == pass) {
      if (fault < 1 || fault > count) ThrowInput("--inject '{}': {} has faults 1..{}", spec, pass, count);
      f[pass] = fault;
      return f;
    }
  }
  ThrowInput("--inject '{}': no kernel named '{}'; kernels: {}", spec, pass, known);
}

// Would a divergence in a ray batch change any hit? Traces both with the emulator's tracer.
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

// Packed (node << 14 | triangle) pairs whose ids are in range.
bool ValidPairs(const std::vector<std::uint32_t>& pairs, std::uint32_t nodes, std::uint32_t tris) {
  for (std::uint32_t p : pairs)
    if ((p >> emu::kPairTriangleBits) >= nodes || (p & ((1u << emu::kPairTriangleBits) - 1u)) >= tris) return false;
  return true;
}

template <typename F>
double TimeMs(F&& f) {
  const auto t0 = std::chrono::steady_clock::now();
  f();
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

int RunDiff(const DiffArgs& args) {
  emu::FrameOptions fo;
  const Scene scene = LoadSceneForFrame(args.scene, args.data, args.size, fo.width, fo.height);
  const gpu_backend::Faults faults = ParseInject(args.inject);

  std::unique_ptr<gpu_backend::VulkanPasses> gpu;
  if (vk::Status s = gpu_backend::VulkanPasses::Create(args.device, faults, gpu, static_cast<std::uint32_t>(args.local_size)); !s) {
    if (s.message.rfind("--device", 0) == 0) ThrowInput("{}", s.message);  // a bad argument, not a failure
    throw std::runtime_error("Vulkan: " + s.message);
  }

  // The emulated frame provides the inputs of the first kernel passes (G-buffer surfaces) and the
  // accumulator for resolve.
  const SceneBuffers buffers = FlattenScene(scene);
  auto direct = emu::MakeDirectTracer(buffers, emu::DirectMode::kAuto);
  const emu::FrameResult frame = emu::RenderFrame(scene, buffers, *direct, fo);
  const gpu::FrameConstants fc = MakeFrameConstants(scene, buffers, fo.width, fo.height);
  std::vector<gpu::Surface> surfaces;

  std::vector<BufferComparison> results;
  nlohmann::json passes = nlohmann::json::array();
  std::string first_divergent;
  double emu_ms = 0.0, gpu_ms = 0.0;  // the latest pass's times on each backend
  std::vector<std::string> stopped;   // passes not compared because an earlier output was unusable
  auto record = [&](const std::string& pass, std::vector<BufferComparison> cmp, const std::string& note) {
    bool equal = true;
    nlohmann::json bl = nlohmann::json::array();
    for (const BufferComparison& c : cmp) {
      equal &= c.Equal();
      nlohmann::json cj;
      c.ToJson(cj);
      bl.push_back(cj);
      std::printf("  %-16s %s\n", pass.c_str(), c.Summary().c_str());
    }
    if (!equal && first_divergent.empty()) first_divergent = pass;
    std::printf("  %-16s emu %.1f ms, vulkan %.1f ms\n", pass.c_str(), emu_ms, gpu_ms);
    passes.push_back({{"pass", pass}, {"equal", equal}, {"buffers", bl}, {"hits", note}, {"emu_ms", emu_ms}, {"vulkan_ms", gpu_ms}});
  };
  auto fail = [](const vk::Status& s) {
    if (!s) throw std::runtime_error("Vulkan: " + s.message);
  };

  std::printf("rayspace diff: %s (%dx%d) on %s; emulation model %s\n", scene.name.c_str(), fo.width, fo.height,
              gpu->context().device_name().c_str(), EmulationModel().c_str());
  // raster: lavapipe's fixed-function coverage, clipping and depth test against the emulation.
  emu::GBuffer gpu_gbuffer;
  {
    emu_ms = 0.0;
    for (const emu::PassRecord& p : frame.passes)
      if (p.name == "raster") emu_ms = p.ms;
    gpu_ms = TimeMs([&] { fail(gpu->Raster(fc, buffers, gpu_gbuffer)); });
    const emu::GBuffer& e = frame.gbuffer;
    record("raster",
           {CompareBuffers("raster", "diffuse", e.diffuse, gpu_gbuffer.diffuse, 0xFu),
            CompareBuffers("raster", "specular", e.specular, gpu_gbuffer.specular, 0xFu),
            CompareBuffers("raster", "position", e.position, gpu_gbuffer.position, 0xFu),
            CompareBuffers("raster", "normal", e.normal, gpu_gbuffer.normal, 0xFu),
            CompareBuffers("raster", "prim", e.prim, gpu_gbuffer.prim, 0),
            CompareBuffers("raster", "depth", e.depth, gpu_gbuffer.depth, 1u)},
           "");
  }
  // From here on both sides read the GPU's outputs, starting with its G-buffer.
  std::vector<gpu::Surface> gpu_surfaces;
  gpu_ms = TimeMs([&] { fail(gpu->Surfaces(fc, gpu_gbuffer, buffers, gpu_surfaces)); });
  emu_ms = TimeMs([&] { surfaces = emu::PassSurfacesFromGBuffer(fc, gpu_gbuffer, buffers); });
  record("surfaces", {CompareBuffers("surfaces", "surfaces", surfaces, gpu_surfaces, kSurfaceFloats)}, "");

  // CRSH's ray sorting and hierarchy build on a batch of GPU-compacted rays: hash, compress, sort,
  // decompress, then level-1 nodes (8 rays each) and one level of unions. The kernels serve every
  // batch; their planted faults are named after the shadow batch, which runs first.
  auto SortAndBuild = [&](const std::string& kind, const std::vector<gpu::Ray>& rays) {
    const emu::HashConfig hc;
    std::vector<std::uint32_t> gpu_keys, gpu_sorted, gpu_order;
    gpu_ms = TimeMs([&] { fail(gpu->Hash(rays, fc, hc, gpu_keys)); });
    std::vector<std::uint32_t> emu_keys;
    emu_ms = TimeMs([&] { emu_keys = emu::PassHash(rays, buffers, hc); });
    record("hash." + kind, {CompareBuffers("hash." + kind, "keys", emu_keys, gpu_keys, 0)}, "");
    emu::Chunks gpu_chunks;
    gpu_ms = TimeMs([&] { fail(gpu->Compress(gpu_keys, gpu_chunks)); });
    emu::Chunks emu_chunks;
    emu_ms = TimeMs([&] { emu_chunks = emu::PassCompress(gpu_keys); });
    record("compress." + kind,
           {CompareBuffers("compress." + kind, "chunk_key", emu_chunks.key, gpu_chunks.key, 0),
            CompareBuffers("compress." + kind, "chunk_base", emu_chunks.base, gpu_chunks.base, 0),
            CompareBuffers("compress." + kind, "chunk_size", emu_chunks.size, gpu_chunks.size, 0)},
           "");
    gpu_ms = TimeMs([&] { fail(gpu->SortChunks(gpu_chunks.key, gpu_sorted)); });
    std::vector<std::uint32_t> emu_sorted;
    emu_ms = TimeMs([&] { emu_sorted = emu::PassSortChunks(gpu_chunks.key); });
    record("sort." + kind, {CompareBuffers("sort." + kind, "chunk_order", emu_sorted, gpu_sorted, 0)}, "");
    gpu_ms = TimeMs([&] { fail(gpu->Decompress(gpu_chunks, gpu_sorted, gpu_order)); });
    std::vector<std::uint32_t> emu_order;
    emu_ms = TimeMs([&] { emu_order = emu::PassDecompress(gpu_chunks, gpu_sorted); });
    record("decompress." + kind, {CompareBuffers("decompress." + kind, "ray_order", emu_order, gpu_order, 0)}, "");

    // build: level-1 nodes over the GPU's sorted rays (8 per node), then one level of unions.
    const std::vector<std::uint32_t> first1 = emu::FixedGroups(gpu_order.size(), 8);
    std::vector<gpu::ConeNode> emu_l1, gpu_l1, emu_l2, gpu_l2;
    emu_ms = TimeMs([&] { emu_l1 = emu::PassBuildLeaves(rays, gpu_order, first1); });
    gpu_ms = TimeMs([&] { fail(gpu->BuildLeaves(rays, gpu_order, first1, gpu_l1)); });
    const std::vector<std::uint32_t> first2 = emu::FixedGroups(gpu_l1.size(), 8);
    double emu2 = TimeMs([&] { emu_l2 = emu::PassBuildParents(gpu_l1, first2); });
    double gpu2 = TimeMs([&] { fail(gpu->BuildParents(gpu_l1, first2, gpu_l2)); });
    emu_ms += emu2;
    gpu_ms += gpu2;
    record("build." + kind,
           {CompareBuffers("build." + kind, "nodes.L1", emu_l1, gpu_l1, kNodeFloats),
            CompareBuffers("build." + kind, "nodes.L2", emu_l2, gpu_l2, kNodeFloats)},
           "");

    // Traversal of one block (top nodes x the first triangle batch, capped at 2^22 slots), stream
    // reduction after each level, and the final tests; each pass reads the GPU's previous output.
    const std::uint32_t T = static_cast<std::uint32_t>(std::min<std::size_t>(buffers.triangles.size(), 1u << 14));
    const std::uint32_t t1 = static_cast<std::uint32_t>(std::min<std::size_t>(gpu_l2.size(), std::max<std::size_t>(1, (1u << 22) / T)));
    const float eps = emu::TraversalEpsilon(buffers);
    const auto& spheres = frame.triangle_spheres;
    auto wide = [](const std::vector<std::uint8_t>& v) { return std::vector<std::uint32_t>(v.begin(), v.end()); };
    auto narrow = [](const std::vector<std::uint32_t>& v) { return std::vector<std::uint8_t>(v.begin(), v.end()); };
    std::vector<std::uint32_t> gf, gv, gt;
    emu::PairSlots es;
    static const std::vector<std::uint8_t> kNoMask;
    emu_ms = TimeMs([&] { es = emu::PassTraverseTop(gpu_l2, 0, t1, 0, T, spheres, buffers, kNoMask, eps); });
    gpu_ms = TimeMs([&] { fail(gpu->TraverseTop(gpu_l2, 0, t1, 0, T, spheres, buffers, eps, gf, gv, gt)); });
    record("traverse." + kind,
           {CompareBuffers("traverse." + kind, "top.flags", wide(es.flags), gf, 0),
            CompareBuffers("traverse." + kind, "top.pairs", es.values, gv, 0),
            CompareBuffers("traverse." + kind, "top.tested", wide(es.tested), gt, 0)},
           "");
    std::vector<std::uint32_t> gpairs, epairs;
    emu_ms = TimeMs([&] { epairs = emu::ReduceHierarchical(narrow(gf), gv, 64); });
    gpu_ms = TimeMs([&] { fail(gpu->Reduce(gf, gv, 64, gpairs)); });
    record("reduce." + kind, {CompareBuffers("reduce." + kind, "top.pairs", epairs, gpairs, 0)}, "");
    // A diverged pair stream may hold garbage ids; stop this batch rather than index with them.
    if (!ValidPairs(gpairs, t1, T)) {
      stopped.push_back("traverse." + kind + ".L1 and after: the GPU's pair stream holds ids out of range");
      return;
    }
    emu_ms = TimeMs([&] { es = emu::PassTraverseLevel(gpairs, gpu_l1, first2, 0, 0, 8, 0, spheres, eps); });
    gpu_ms = TimeMs([&] { fail(gpu->TraverseLevel(gpairs, gpu_l1, first2, 0, 0, 8, 0, spheres, eps, gf, gv, gt)); });
    record("traverse." + kind + ".L1",
           {CompareBuffers("traverse." + kind + ".L1", "flags", wide(es.flags), gf, 0),
            CompareBuffers("traverse." + kind + ".L1", "pairs", es.values, gv, 0),
            CompareBuffers("traverse." + kind + ".L1", "tested", wide(es.tested), gt, 0)},
           "");
    emu_ms = TimeMs([&] { epairs = emu::ReduceHierarchical(narrow(gf), gv, 64); });
    gpu_ms = TimeMs([&] { fail(gpu->Reduce(gf, gv, 64, gpairs)); });
    record("reduce." + kind + ".L1", {CompareBuffers("reduce." + kind + ".L1", "pairs", epairs, gpairs, 0)}, "");
    if (!ValidPairs(gpairs, static_cast<std::uint32_t>(gpu_l1.size()), T)) {
      stopped.push_back("intersect." + kind + ": the GPU's pair stream holds ids out of range");
      return;
    }
    const bool shadow = kind == "shadow";
    std::vector<std::uint64_t> eh(rays.size(), emu::kMissPacked), gh;
    std::vector<std::uint32_t> eo(rays.size(), 0u), go, etests, gtests;
    emu_ms = TimeMs([&] { etests = emu::PassIntersect(gpairs, first1, 0, 0, gpu_order, rays, buffers, shadow ? nullptr : &eh, shadow ? &eo : nullptr); });
    gpu_ms = TimeMs([&] { fail(gpu->Intersect(gpairs, first1, 0, 0, gpu_order, rays, buffers, shadow, gh, go, gtests)); });
    std::vector<BufferComparison> ic = {CompareBuffers("intersect." + kind, "tests", etests, gtests, 0)};
    if (shadow) ic.push_back(CompareBuffers("intersect." + kind, "occluded", eo, go, 0));
    else ic.push_back(CompareBuffers("intersect." + kind, "hits", eh, gh, 0));
    record("intersect." + kind, ic, "");
  };

  emu::SparseRays gpu_rays;
  emu::Trimmed gpu_trim;
  std::vector<std::uint32_t> occluded;
  if (!scene.lights.empty()) {
    emu::SparseRays emu_rays;
    emu_ms = TimeMs([&] { emu_rays = emu::PassRaygenShadow(fc, gpu_surfaces, buffers); });
    gpu_ms = TimeMs([&] { fail(gpu->RaygenShadow(fc, gpu_surfaces, buffers, gpu_rays)); });
    record("raygen.shadow",
           {CompareBuffers("raygen.shadow", "rays", emu_rays.rays, gpu_rays.rays, kRayFloats),
            CompareBuffers("raygen.shadow", "flags", emu_rays.flags, gpu_rays.flags, 0)},
           "");
    emu::Trimmed emu_trim;
    emu_ms = TimeMs([&] { emu_trim = emu::PassTrim(gpu_rays); });
    gpu_ms = TimeMs([&] { fail(gpu->Trim(gpu_rays, gpu_trim)); });
    direct->Occluded(gpu_trim.rays, occluded);
    const std::string hits = HitsChanged(*direct, emu_trim.rays, gpu_trim.rays, true);
    record("trim.shadow",
           {CompareBuffers("trim.shadow", "offsets", emu_trim.offsets, gpu_trim.offsets, 0),
            CompareBuffers("trim.shadow", "rays", emu_trim.rays, gpu_trim.rays, kRayFloats)},
           hits);

    SortAndBuild("shadow", gpu_trim.rays);
  }
  // shade.b0: the GPU's surfaces, shadow rays and (emulated) occlusion on both sides.
  std::vector<std::uint64_t> emu_accum(static_cast<std::size_t>(fo.width) * fo.height * 3, 0), gpu_accum = emu_accum;
  emu_ms = TimeMs([&] { emu::PassShade(fc, gpu_surfaces, gpu_rays.flags, gpu_trim.offsets, occluded, buffers, emu_accum); });
  gpu_ms = TimeMs([&] { fail(gpu->Shade(gpu_surfaces, gpu_rays.flags, gpu_trim.offsets, occluded, buffers, gpu_accum)); });
  record("shade", {CompareBuffers("shade", "accum", emu_accum, gpu_accum, 0)}, "");

  bool reflective = false;
  for (const MaterialDesc& m : scene.materials) reflective |= m.reflectivity > 0.0f;
  if (reflective && scene.max_depth > 0) {
    emu::SparseRays emu_refl, gpu_refl;
    emu_ms = TimeMs([&] { emu_refl = emu::PassRaygenReflection(fc, gpu_surfaces, buffers); });
    gpu_ms = TimeMs([&] { fail(gpu->RaygenReflection(fc, gpu_surfaces, buffers, gpu_refl)); });
    record("raygen.reflection",
           {CompareBuffers("raygen.reflection", "rays", emu_refl.rays, gpu_refl.rays, kRayFloats),
            CompareBuffers("raygen.reflection", "flags", emu_refl.flags, gpu_refl.flags, 0)},
           "");
    emu::Trimmed emu_rt, gpu_rt;
    emu_ms = TimeMs([&] { emu_rt = emu::PassTrim(gpu_refl); });
    gpu_ms = TimeMs([&] { fail(gpu->Trim(gpu_refl, gpu_rt, true)); });
    const std::string hits = HitsChanged(*direct, emu_rt.rays, gpu_rt.rays, false);
    record("trim.reflection",
           {CompareBuffers("trim.reflection", "offsets", emu_rt.offsets, gpu_rt.offsets, 0),
            CompareBuffers("trim.reflection", "rays", emu_rt.rays, gpu_rt.rays, kRayFloats)},
           hits);
    SortAndBuild("reflection", gpu_rt.rays);
  }
  bool transparent = false;
  for (const MaterialDesc& m : scene.materials) transparent |= m.transparency > 0.0f;
  if (transparent && scene.max_depth > 0) {
    emu::SparseRays emu_refr, gpu_refr;
    emu_ms = TimeMs([&] { emu_refr = emu::PassRaygenRefraction(fc, gpu_surfaces, buffers); });
    gpu_ms = TimeMs([&] { fail(gpu->RaygenRefraction(fc, gpu_surfaces, buffers, gpu_refr)); });
    record("raygen.refraction",
           {CompareBuffers("raygen.refraction", "rays", emu_refr.rays, gpu_refr.rays, kRayFloats),
            CompareBuffers("raygen.refraction", "flags", emu_refr.flags, gpu_refr.flags, 0)},
           "");
    emu::Trimmed emu_ft, gpu_ft;
    emu_ms = TimeMs([&] { emu_ft = emu::PassTrim(gpu_refr); });
    gpu_ms = TimeMs([&] { fail(gpu->Trim(gpu_refr, gpu_ft, true)); });
    record("trim.refraction",
           {CompareBuffers("trim.refraction", "offsets", emu_ft.offsets, gpu_ft.offsets, 0),
            CompareBuffers("trim.refraction", "rays", emu_ft.rays, gpu_ft.rays, kRayFloats)},
           HitsChanged(*direct, emu_ft.rays, gpu_ft.rays, false));
  }
  std::vector<std::uint8_t> gpu_rgb;
  gpu_ms = TimeMs([&] { fail(gpu->Resolve(fc, frame.accum, gpu_rgb)); });
  std::vector<std::uint8_t> emu_rgb;
  emu_ms = TimeMs([&] { emu_rgb = emu::PassResolve(fc, frame.accum); });
  const std::vector<std::uint32_t> emu_wide(emu_rgb.begin(), emu_rgb.end()), gpu_wide(gpu_rgb.begin(), gpu_rgb.end());
  record("resolve", {CompareBuffers("resolve", "rgb", emu_wide, gpu_wide, 0)}, "");

  for (const std::string& st : stopped) std::printf("  not compared: %s\n", st.c_str());
  const bool equal = first_divergent.empty();
  std::printf("  %s\n", equal ? "all passes equal" : ("first divergent pass: " + first_divergent).c_str());
  if (!args.report.empty()) {
    nlohmann::json j = {{"scene", scene.name},
                        {"width", fo.width},
                        {"height", fo.height},
                        {"device", gpu->context().device_name()},
                        {"driver", gpu->context().driver()},
                        {"emulation_model", EmulationModel()},
                        {"inject", args.inject},
                        {"local_size", args.local_size},
                        {"passes", passes},
                        {"emulated_only", {"prep", "trace (direct tracer)", "object-sphere culling", "bounces after the first"}},
                        {"equal", equal},
                        {"stopped", stopped},
                        {"first_divergent_pass", equal ? nlohmann::json(nullptr) : nlohmann::json(first_divergent)}};
    std::ofstream f(args.report);
    if (!f) ThrowInput("{}: cannot write the report", args.report);
    f << j.dump(2) << "\n";
  }
  return equal ? 0 : 4;
}

}  // namespace rayspace::app
