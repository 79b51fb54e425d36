#include "rayspace/frame/render_command.h"

#include "rayspace/output_names.h"
#include "rayspace/frame/command_util.h"

#include <cmath>
#include <cstdio>
#include <optional>

#include <unistd.h>

#include <nlohmann/json.hpp>

#include "rayspace/frame/memory_estimate.h"
#include "rayspace/frame/peak_memory.h"
#include "rayspace/digest.h"
#include "rayspace/error.h"
#include "rayspace/image_io.h"
#include "rayspace/json_text.h"
#include "rayspace/parallel.h"
#include "rayspace/frame/render_frame.h"
#include "rayspace/frame/version.h"

namespace rayspace::app {
namespace {

nlohmann::json RaysJson(const std::vector<std::uint64_t>& per_bounce, bool from_one) {
  std::uint64_t total = 0;
  nlohmann::json pb = nlohmann::json::array();
  for (std::size_t b = from_one ? 1 : 0; b < per_bounce.size(); ++b) {
    total += per_bounce[b];
    pb.push_back({{"bounce", b}, {"rays", per_bounce[b]}});
  }
  return {{"total", total}, {"per_bounce", pb}};
}

// What one render produced, for the statistics file and the summary.
struct Outcome {
  const Scene& scene;
  const Backend& backend;
  const emu::FrameResult& r;
  const refs::Oracle* oracle;  // nullptr with --no-oracle
  double oracle_ms = 0.0;
  std::string out;             // the image written
  nlohmann::json tracer, oracle_json;
  Statistics stats;
  std::vector<Phase> phases;
  std::size_t peak_rss = 0;    // bytes, the process's peak resident set (0: unknown)
  MemoryEstimate estimate{};
};

nlohmann::json OracleJson(const refs::Oracle* oracle, double oracle_ms) {
  nlohmann::json oj;
  if (!oracle) {
    oj = {{"name", "none"}, {"rays_checked", 0}, {"mismatches", 0}, {"skipped", true}};
  } else {
    oracle->Report(oj, 1000);
    oj["ms"] = oracle_ms;
  }
  return oj;
}

nlohmann::json StatsJson(const RenderArgs& args, const Outcome& o) {
  const Scene& scene = o.scene;
  const Backend& backend = o.backend;
  const emu::FrameResult& r = o.r;
  nlohmann::json j;
  j["scene"] = scene.name;
  j["scene_file"] = args.scene;
  j["triangles"] = r.triangles;
  j["objects"] = scene.objects.size();
  j["width"] = r.width;
  j["height"] = r.height;
  j["max_depth"] = scene.max_depth;  // the bounces (--bounces or the scene's), under the scene format's name
  j["bounces"] = scene.max_depth;
  if (o.tracer.contains("depth")) j["hierarchy_levels"] = o.tracer["depth"];  // "levels" holds the per-level counts
  j["lights"] = scene.lights.size();
  j["shadow_rays_per_point"] = ShadowSlotsPerSurface(scene.lights);  // the lights' samples
  j["algorithm"] = args.algo;
  if (args.Hierarchy()) j["path"] = UsesFusedPath(args) ? "fused" : "passes";
  j["backend"] = {{"name", backend.name}, {"device", backend.device}};
  j["tracer"] = o.tracer;
  j["threads"] = ThreadCount();
  j["rays"] = {{"shadow", RaysJson(r.rays[layout::kRayShadow], false)},
               {"reflection", RaysJson(r.rays[layout::kRayReflection], true)},
               {"refraction", RaysJson(r.rays[layout::kRayRefraction], true)},
               {"shadow_unoccluded", RaysJson(r.unoccluded_shadow_rays, false)}};
  if (r.primary_rays > 0)
    j["primary"] = {{"rays", r.primary_rays},
                    {"pixels_differing_from_raster", r.primary_differing},
                    {"frustum_culling", o.tracer.value("frustum_culling", false)}};
  if (scene.HasAreaLight())
    j["soft_shadows"] = {{"penumbra_points", r.penumbra_points},
                         {"umbra_points", r.umbra_points}};
  o.stats.ToJson(j);
  PhasesToJson(j, o.phases);
  j["oracle"] = o.oracle_json;
  nlohmann::json passes = nlohmann::json::array();
  for (const emu::PassRecord& p : r.passes) {
    nlohmann::json pj = {{"name", p.name}, {"ran", p.ran}, {"reason", p.reason}, {"ms", p.ms}, {"elements", p.elements}};
    passes.push_back(pj);
  }
  j["passes"] = passes;
  j["digest"] = HexDigest(r.digest.Frame());
  nlohmann::json buffers_json = nlohmann::json::array();
  for (const auto& e : r.digest.entries())
    buffers_json.push_back({{"pass", e.pass}, {"buffer", e.buffer}, {"bytes", e.bytes}, {"hash", HexDigest(e.hash)}});
  j["buffer_digests"] = buffers_json;
  j["frame_ms"] = r.total_ms;
  j["peak_rss_bytes"] = o.peak_rss;
  j["bytes_per_pixel"] = static_cast<double>(o.peak_rss) / (static_cast<double>(r.width) * r.height);
  j["memory_estimate"] = MemoryEstimateJson(o.estimate);
  if (backend.extra_dispatches) j["backend"]["split_dispatches"] = backend.extra_dispatches(backend);
  if (backend.paged_arrays) j["backend"]["paged_arrays"] = backend.paged_arrays(backend);
  if (backend.max_buffer_bytes) j["backend"]["binding_bytes"] = backend.max_buffer_bytes;
  j["image"] = o.out;
  AddProvenance(j);
  return j;
}

// Human-readable summary.
void PrintSummary(const RenderArgs& args, const Outcome& o) {
  const Scene& scene = o.scene;
  const Backend& backend = o.backend;
  const emu::FrameResult& r = o.r;
  const nlohmann::json& tracer = o.tracer;
  // Soft shadows are named where they run: an area light's samples are shadow rays per point.
  const std::string soft = scene.HasAreaLight()
                               ? fmt::format(", area: {} shadow rays per shading point, soft shadows", ShadowSlotsPerSurface(scene.lights))
                               : "";
  std::printf("rayspace render: %s (%zu triangles in %zu objects, %dx%d, bounces %d from %s, %zu light%s%s)\n",
              scene.name.c_str(), r.triangles, scene.objects.size(), r.width, r.height, scene.max_depth,
              args.bounces >= 0 ? "--bounces" : "the scene's max_depth",
              scene.lights.size(), scene.lights.size() == 1 ? "" : "s", soft.c_str());
  std::string how;
  if (tracer.contains("subdivision"))
    how = fmt::format("subdivision {}, {} hierarchy levels, {} reduction", tracer["subdivision"].get<int>(), tracer["depth"].get<int>(),
                      tracer["reduction"].get<std::string>());
  else if (tracer.contains("lists"))
    how = fmt::format("{} lists, {}{}{}", tracer["lists"].get<std::uint32_t>(), tracer["node_order"].get<std::string>(),
                      tracer.value("backface_culling", false) ? ", back-face culling: one-sided triangles" : "",
                      tracer.value("polygon_heads", std::string("off")) != "off"
                          ? ", " + tracer["polygon_heads"].get<std::string>() + " per-polygon heads"
                          : std::string());
  else if (tracer.contains("perspective_cells_per_face"))
    how = fmt::format("perspective grids of 6 x {}^2 cells per point light, regular grid {}", tracer["perspective_cells_per_face"].get<std::uint32_t>(),
                      tracer.contains("regular_dims") ? fmt::format("{}x{}x{}", tracer["regular_dims"][0].get<std::uint32_t>(),
                                                                    tracer["regular_dims"][1].get<std::uint32_t>(),
                                                                    tracer["regular_dims"][2].get<std::uint32_t>())
                                                      : std::string("unbuilt"));
  else
    how = tracer.value("mode", tracer.value("isa", std::string()));
  std::printf("  backend     %s (%s%s)\n", backend.name.c_str(), backend.device.c_str(),
              backend.extra_dispatches ? fmt::format(", {} split dispatches, {} paged arrays", backend.extra_dispatches(backend),
                                                     backend.paged_arrays(backend)).c_str()
                                       : "");
  std::printf("  tracer      %s (%s)\n", args.algo.c_str(), how.c_str());
  for (std::uint32_t k = 0; k < 3; ++k) {
    std::string per;
    for (std::size_t b = k == 0 ? 0 : 1; b < r.rays[k].size(); ++b)
      per += fmt::format("{}b{}={}", per.empty() ? "" : " ", b, r.rays[k][b]);
    std::printf("  %-11s %s\n", emu::RayKindName(k), per.empty() ? "-" : per.c_str());
  }
  if (r.primary_rays > 0)
    std::printf("  primary     %llu eye rays traced beside the raster%s; %llu pixels differ from the raster's primitive\n",
                static_cast<unsigned long long>(r.primary_rays), tracer.value("frustum_culling", false) ? " (frustum culling)" : "",
                static_cast<unsigned long long>(r.primary_differing));
  if (scene.HasAreaLight()) {
    std::string per;
    for (std::size_t b = 0; b < r.penumbra_points.size(); ++b)
      per += fmt::format("{}b{}={}/{}", per.empty() ? "" : " ", b, r.penumbra_points[b], r.umbra_points[b]);
    std::printf("  soft        %zu shadow rays per shading point; points in penumbra/umbra of an area light: %s\n",
                ShadowSlotsPerSurface(scene.lights), per.empty() ? "-" : per.c_str());
  }
  for (const emu::PassRecord& p : r.passes)
    if (!p.ran && p.name.rfind("trace.", 0) == 0) std::printf("  skipped     %s: %s\n", p.name.c_str(), p.reason.c_str());
  o.stats.Print(stdout);
  if (args.timings) PrintPhases(stdout, o.phases, r.total_ms, o.stats.tests_counted ? std::optional<std::uint64_t>(o.stats.total) : std::nullopt);
  if (!o.oracle) {
    std::printf("  oracle      skipped\n");
  } else {
    std::printf("  oracle      %s: %zu rays checked, %zu mismatches; exact arithmetic found the oracle wrong on %zu, %zu exact ties (shared edges, grazed edges), %zu within rounding\n",
                o.oracle_json["name"].get<std::string>().c_str(), o.oracle->rays_checked(), o.oracle->mismatches().size(),
                o.oracle->oracle_wrong().size(), o.oracle->ties().size(), o.oracle->within_rounding().size());
    if (o.tracer.value("closed_models", false))
      std::printf("  culling     --closed-models changed %zu shadow results against the oracle (front-face culling assumes closed meshes)\n",
                  o.oracle->shadow_changes().size());
  }
  std::printf("  frame       %.1f ms (oracle %.1f ms)\n", r.total_ms, o.oracle_ms);
  if (o.peak_rss)
    std::printf("  memory      %.1f MB peak resident (%.0f bytes per pixel); estimated before the frame %.1f MB\n",
                static_cast<double>(o.peak_rss) / 1e6, static_cast<double>(o.peak_rss) / (static_cast<double>(r.width) * r.height),
                static_cast<double>(o.estimate.total) / 1e6);
  std::printf("  digest      %s\n", HexDigest(r.digest.Frame()).c_str());
  std::printf("  image       %s\n", o.out.c_str());
  if (!args.stats.empty()) std::printf("  stats       %s\n", args.stats.c_str());
}

// The image and the statistics file, checked before the frame (a bad path costs no render).
struct RenderOutputs {
  OutputFile image, stats;
};

RenderOutputs OpenRenderOutputs(const RenderArgs& args, const Scene& scene) {
  RenderOutputs o;
  const std::string image = args.out.empty() ? SceneOutputStem(scene, "give --out to name the image") + ".png" : args.out;
  CheckImageFormat(image);
  o.image = OpenOutput(image, "the output image", &scene, false);
  o.stats = OpenOutput(args.stats, "the statistics file", &scene);
  CheckDistinctOutputs({&o.image, &o.stats});
  return o;
}

// Exit 3's reason, on stderr: the summary on stdout says how many rays, this line which came first.
void PrintMismatchVerdict(const refs::Oracle& oracle) {
  const refs::Disagreement& d = oracle.mismatches().front();
  const bool shadow = d.batch.rfind("shadow", 0) == 0;  // prim holds the occluded flag there, told by the note
  auto hit = [](std::uint32_t prim, float t) {
    return prim == layout::kNoPrim ? std::string("miss") : fmt::format("triangle {} at t {}", prim, t);
  };
  const std::string what = shadow ? d.note
                                  : fmt::format("frame {}, oracle {}{}{}", hit(d.frame_prim, d.frame_t), hit(d.oracle_prim, d.oracle_t),
                                                d.note.empty() ? "" : ": ", d.note);
  std::fprintf(stderr, "rayspace render: the oracle found %zu ray(s) the frame got wrong; first: %s ray %zu: %s\n",
               oracle.mismatches().size(), d.batch.c_str(), d.ray, what.c_str());
}

}  // namespace

RenderValue RenderToValue(const RenderArgs& args, const std::function<std::string(const Scene&)>& on_scene) {
  const ScopedSettings threads([&](Settings& s) { s.threads = args.threads > 0 ? args.threads : s.threads; });
  const bool one_sided = OneSided(args);  // before any work: a bad switch fails first
  emu::FrameOptions fo;
  const Scene scene = LoadSceneForFrame(args.scene, args.data, args.size, fo.width, fo.height, args.bounces);
  fo.progress = args.progress || isatty(STDERR_FILENO);  // progress on stderr when someone watches
  ApplyFaithful(args.faithful, fo);
  ApplyPrimary(args, fo);
  const std::string image = on_scene ? on_scene(scene) : std::string();

  const MemoryEstimate estimate = EstimateFrameMemory(scene, fo.width, fo.height, RenderMemoryUse(args));
  CheckFitsMachine(estimate, fo.width, fo.height, SizeFrom(args.size, scene).c_str());

  const Backend backend = MakeRenderBackend(args);
  SceneBuffers buffers = FlattenForFrame(scene, args.faithful);
  buffers.one_sided = one_sided;
  CheckFrameFits(backend, fo.width, fo.height, ShadowSlotsPerSurface(scene.lights), buffers.triangles.size(),
                 SizeFrom(args.size, scene));
  const std::unique_ptr<RenderedFrame> f = RenderOnBackend(args, scene, buffers, fo, backend);
  CheckKernelsRan(backend, args.kernels);  // before any summary: a kernel that never ran has no verdict
  const emu::FrameResult& r = f->result;

  const refs::Oracle* checked = f->oracle ? &*f->oracle : nullptr;
  const Outcome o{scene, backend, r, checked, f->oracle_ms, image, f->tracer,
                  OracleJson(checked, f->oracle_ms), f->stats, f->phases, PeakRssBytes(), estimate};
  PrintSummary(args, o);
  const bool wrong = checked && !checked->mismatches().empty();
  if (wrong) PrintMismatchVerdict(*checked);
  RenderValue v;
  v.verdict = wrong ? ExitCode::kOracleMismatch : ExitCode::kOk;
  v.width = r.width;
  v.height = r.height;
  v.digest = HexDigest(r.digest.Frame());
  v.oracle_mismatches = checked ? checked->mismatches().size() : 0;
  v.statistics = StatsJson(args, o);
  v.rgb = std::move(f->result.rgb);  // last: nothing reads the frame's pixels after this
  return v;
}

ExitCode RunRender(const RenderArgs& args) {
  std::optional<RenderOutputs> outputs;
  const RenderValue v = RenderToValue(args, [&](const Scene& scene) {
    outputs.emplace(OpenRenderOutputs(args, scene));
    return outputs->image.path();
  });
  return WriteOutputs(v.verdict, [&] {
    WriteImage(outputs->image, v.width, v.height, v.rgb);
    outputs->stats.Write(JsonText(v.statistics));
    PublishAll({&outputs->image, &outputs->stats});
  });
}

}  // namespace rayspace::app
