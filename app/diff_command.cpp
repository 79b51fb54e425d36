#include "diff_command.h"
#include "backend_setup.h"
#include "cli_util.h"
#include "kernel_model.h"

#include <cmath>
#include <cstddef>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "rayspace/emu/frame.h"
#include "rayspace/emu/hierarchy.h"
#include "rayspace/emu/workgroup_ops.h"
#include "rayspace/error.h"
#include "rayspace/input_file.h"
#include "rayspace/gpu/passes.h"
#include "rayspace/pass_registry.h"
#include "rayspace/refs/embree_tracer.h"
#include "rayspace/scene.h"
#include "rayspace/verify/differ.h"

namespace rayspace::app {
namespace {

std::string EmulationModel() {
  std::string m = "x86-64";
#if defined(__x86_64__)
  __builtin_cpu_init();
  if (__builtin_cpu_supports("avx512f")) m += " avx512f";
  else if (__builtin_cpu_supports("avx2")) m += " avx2";
  if (__builtin_cpu_supports("fma")) m += " fma";
#endif
  return m + "; emulated kernels use no FMA contraction (-ffp-contract=off) and only correctly rounded +,-,*,/,sqrt";
}

bool InDomain(const glm::vec4& v) {
  for (int k = 0; k < 3; ++k)
    if (!(std::fabs(static_cast<double>(v[k])) <= kMaxCoordinate)) return false;  // also NaN
  return true;
}

}  // namespace

// A saved call's inputs must be ones a render could have made (a hand-edited set may hold anything):
// triangles inside the scene loader's coordinate domain (beyond it clip coordinates overflow and
// the raster clipper's bounds no longer hold), a finite frame whose size the passes can allocate
// and whose counts match the saved scene (the passes loop over dims.z triangles and dims.w lights).
void CheckSavedInputs(const verify::BufferSet& in, const std::string& dir) {
  if (in.Has("scene.triangles")) {
    const std::vector<layout::Triangle> tris = in.Get<layout::Triangle>("scene.triangles");
    for (std::size_t i = 0; i < tris.size(); ++i)
      if (!InDomain(tris[i].v0) || !InDomain(tris[i].v1) || !InDomain(tris[i].v2))
        ThrowInput("{}/scene.triangles.bin: triangle {} leaves the coordinate domain |x| <= 2^62", dir, i);
  }
  if (!in.Has("frame")) return;
  const layout::FrameConstants fc = in.GetOne<layout::FrameConstants>("frame");
  const float* f = &fc.view_proj[0][0];
  for (std::size_t i = 0; i < offsetof(layout::FrameConstants, dims) / sizeof(float); ++i)
    if (!std::isfinite(f[i])) ThrowInput("{}/frame.bin: float {} is {}, expected a finite number", dir, i, f[i]);
  const auto side = static_cast<std::uint32_t>(kMaxImageSide);
  if (fc.dims.x < 1 || fc.dims.y < 1 || fc.dims.x > side || fc.dims.y > side)
    ThrowInput("{}/frame.bin: image size {} x {} out of range [1, {}]", dir, fc.dims.x, fc.dims.y, side);
  if (in.Has("scene.triangles") && in.Has("scene.lights")) {
    const SceneBuffers scene = in.GetScene();
    if (fc.dims.z != scene.triangles.size() || fc.dims.w != scene.lights.size())
      ThrowInput("{}/frame.bin: counts {} triangles and {} lights, the saved scene holds {} and {}", dir, fc.dims.z,
                 fc.dims.w, scene.triangles.size(), scene.lights.size());
  }
}

namespace {

// DIR/comparison.json as diff --save-inputs writes it: an object whose optional 'equal' is a boolean,
// 'inject' a string and 'buffers' an array of objects (each with an optional string 'pass').
void CheckRecorded(const nlohmann::json& j, const std::string& file) {
  if (!j.is_object()) ThrowInput("{}: expected a JSON object, got {}", file, j.type_name());
  if (j.contains("equal") && !j["equal"].is_boolean()) ThrowInput("{}: 'equal' must be a boolean", file);
  if (j.contains("inject") && !j["inject"].is_string()) ThrowInput("{}: 'inject' must be a string", file);
  if (!j.contains("buffers")) return;
  if (!j["buffers"].is_array()) ThrowInput("{}: 'buffers' must be an array", file);
  for (std::size_t i = 0; i < j["buffers"].size(); ++i) {
    const nlohmann::json& b = j["buffers"][i];
    if (!b.is_object() || (b.contains("pass") && !b["pass"].is_string()))
      ThrowInput("{}: buffers[{}] must be an object with a string 'pass'", file, i);
  }
}

nlohmann::json CallJson(const verify::CallRecord& c) {
  nlohmann::json bl = nlohmann::json::array();
  for (const BufferComparison& b : c.buffers) {
    nlohmann::json j;
    b.ToJson(j);
    bl.push_back(j);
  }
  nlohmann::json j = {{"seq", c.seq}, {"pass", c.pass}, {"method", c.method}, {"label", c.label}, {"equal", c.equal},
                      {"buffers", bl}, {"emu_ms", c.expected_ms}, {"vulkan_ms", c.actual_ms}};
  if (!c.hits.empty()) j["hits"] = c.hits;
  if (!c.raster.empty()) j["raster"] = c.raster;
  if (!c.spec.empty()) j["relaxed_model"] = c.spec;
  if (!c.equal) j["within_spec"] = c.within_spec;
  if (!c.error.empty()) j["error"] = c.error;
  if (!c.saved.empty()) j["saved"] = c.saved;
  return j;
}

// Per kernel pass: calls, elements and mismatches per buffer, the first divergent call, and times.
struct PassTotals {
  std::size_t calls = 0, first_seq = 0;
  std::map<std::string, std::pair<std::size_t, std::size_t>> buffers;  // elements, mismatches
  double emu_ms = 0, vulkan_ms = 0;
  bool equal = true;
  const verify::CallRecord* first_divergent = nullptr;
  std::uint64_t max_ulp = 0;
};

// The calls grouped per kernel pass, in order of first appearance, and the first divergent call.
struct DiffTotals {
  std::vector<std::string> order;
  std::map<std::string, PassTotals> totals;
  const verify::CallRecord* first = nullptr;
  std::size_t within_spec = 0;                           // calls that differ only as a device may
  const verify::CallRecord* first_within = nullptr;
};

DiffTotals Totals(const std::vector<verify::CallRecord>& calls) {
  DiffTotals d;
  std::vector<std::string>& order = d.order;
  std::map<std::string, PassTotals>& totals = d.totals;
  const verify::CallRecord*& first = d.first;
  for (const verify::CallRecord& c : calls) {
    auto [it, fresh] = totals.try_emplace(c.pass);
    if (fresh) order.push_back(c.pass);
    PassTotals& t = it->second;
    ++t.calls;
    t.emu_ms += c.expected_ms;
    t.vulkan_ms += c.actual_ms;
    for (const BufferComparison& b : c.buffers) {
      auto& e = t.buffers[b.buffer];
      e.first += b.elements;
      e.second += b.mismatches + (b.expected_elements != b.actual_elements ? 1 : 0);
      t.max_ulp = std::max(t.max_ulp, b.max_ulp);
    }
    if (!c.equal && c.within_spec) {
      ++d.within_spec;
      if (!d.first_within) d.first_within = &c;
      continue;
    }
    if (!c.equal && t.equal) {
      t.equal = false;
      t.first_divergent = &c;
      if (!first) first = &c;
    }
  }
  return d;
}

// Prints one line per kernel pass and returns the same as the report's "passes".
nlohmann::json PrintPasses(DiffTotals& d) {
  nlohmann::json passes = nlohmann::json::array();
  std::printf("  %-18s %6s %12s %11s %11s  %s\n", "pass", "calls", "mismatches", "emu ms", "vulkan ms", "buffers (elements)");
  for (const std::string& p : d.order) {
    const PassTotals& t = d.totals[p];
    std::size_t mism = 0;
    std::string bufs;
    nlohmann::json bj = nlohmann::json::array();
    for (const auto& [name, em] : t.buffers) {
      mism += em.second;
      bufs += fmt::format("{}{} ({})", bufs.empty() ? "" : ", ", name, em.first);
      bj.push_back({{"buffer", name}, {"elements", em.first}, {"mismatches", em.second}});
    }
    std::printf("  %-18s %6zu %12zu %11.1f %11.1f  %s\n", p.c_str(), t.calls, mism, t.emu_ms, t.vulkan_ms, bufs.c_str());
    nlohmann::json pj = {{"pass", p}, {"calls", t.calls}, {"equal", t.equal}, {"buffers", bj}, {"max_ulp", t.max_ulp},
                         {"emu_ms", t.emu_ms}, {"vulkan_ms", t.vulkan_ms}};
    if (t.first_divergent) pj["first_divergent_call"] = CallJson(*t.first_divergent);
    passes.push_back(pj);
  }
  return passes;
}

// Calls that differ only as a conformant device may (relaxed comparison): how many, and the first.
void PrintWithinSpec(const DiffTotals& d) {
  if (!d.first_within) return;
  const verify::CallRecord& c = *d.first_within;
  std::printf("  within the spec's precision: %zu call(s) differ only as a conformant device may; first %s at %s (call %zu)\n",
              d.within_spec, c.pass.c_str(), c.label.c_str(), c.seq);
  if (!c.spec.empty()) std::printf("    %s\n", c.spec.c_str());
  if (!c.raster.empty()) std::printf("    raster: %s\n", c.raster.c_str());
}

void PrintFirstDivergence(const verify::CallRecord* first) {
  if (first) {
    std::printf("  first divergence: %s at %s (call %zu)\n", first->pass.c_str(), first->label.c_str(), first->seq);
    if (!first->error.empty()) std::printf("    %s\n", first->error.c_str());
    for (const BufferComparison& b : first->buffers)
      if (!b.Equal()) std::printf("    %s\n", b.Summary().c_str());
    if (!first->hits.empty()) std::printf("    hits: %s\n", first->hits.c_str());
    if (!first->raster.empty()) std::printf("    raster: %s\n", first->raster.c_str());
    if (!first->spec.empty()) std::printf("    relaxed model: %s\n", first->spec.c_str());
  }
}

// The workgroup checker's reports (an emulated kernel raced, read an unwritten shared word or hit a
// divergent barrier) on stdout, at most 10 lines, and as the report's "workgroup_checker".
nlohmann::json PrintCheckerReports(const wg::CheckResult& r) {
  const std::string dispatch = r.reports.empty() ? std::string("?") : r.reports.front().dispatch;
  const std::optional<PassId> pass = PassOfLabel(dispatch);
  nlohmann::json j = {{"pass", pass ? std::string(Pass(*pass).name) : dispatch},
                      {"dispatch", dispatch},
                      {"count", r.reports.size() + r.dropped},
                      {"reports", nlohmann::json::array()}};
  // Kinds by what they say of the kernel: a divergent barrier or a race is the cause, an unwritten read
  // usually its consequence. The printed lines follow this order.
  constexpr wg::ReportKind kOrder[] = {wg::ReportKind::kDivergentBarrier, wg::ReportKind::kBarrierInPhase,
                                       wg::ReportKind::kRace,             wg::ReportKind::kOutOfBounds,
                                       wg::ReportKind::kInvalidLane,      wg::ReportKind::kUninitialisedRead};
  std::string kinds;
  std::vector<const wg::Report*> ordered;
  for (wg::ReportKind k : kOrder) {
    if (const std::size_t n = r.Count(k)) kinds += fmt::format("{}{} {}", kinds.empty() ? "" : ", ", n, wg::ToString(k));
    for (const wg::Report& rep : r.reports)
      if (rep.kind == k) ordered.push_back(&rep);
  }
  std::printf("  workgroup checker: %zu report(s) in %s (pass %s): %s\n", r.reports.size() + r.dropped, dispatch.c_str(),
              j["pass"].get<std::string>().c_str(), kinds.c_str());
  for (std::size_t k = 0; k < ordered.size(); ++k) {
    const wg::Report& rep = *ordered[k];
    if (k < 10) std::printf("    %s\n", rep.message.c_str());
    j["reports"].push_back({{"kind", wg::ToString(rep.kind)}, {"workgroup", rep.workgroup}, {"phase", rep.phase},
                            {"array", rep.array}, {"word", rep.word}, {"invocations", {rep.inv_a, rep.inv_b}},
                            {"message", rep.message}});
  }
  return j;
}

// The --report file: the run, every pass's totals and every call.
void WriteDiffReport(const DiffArgs& args, const Scene& scene, const emu::FrameOptions& fo, const Backend& gpu,
                     const verify::Differ& differ, const nlohmann::json& passes, bool equal, const std::string& stopped,
                     const verify::CallRecord* first, const emu::FrameResult& frame, const nlohmann::json& checker,
                     bool relaxed, std::size_t within_spec) {
  nlohmann::json calls = nlohmann::json::array();
  for (const verify::CallRecord& c : differ.calls()) calls.push_back(CallJson(c));
  nlohmann::json j = {{"scene", scene.name},
                      {"width", fo.width},
                      {"height", fo.height},
                      {"algorithm", args.algo},
                      {"device", gpu.device},
                      {"emulation_model", EmulationModel()},
                      {"inject", args.inject},
                      {"planted_fault_seen", args.inject.empty() ? nlohmann::json(nullptr) : nlohmann::json(!equal || within_spec > 0)},
                      {"comparison", relaxed ? "relaxed" : "bitwise"},
                      {"calls_within_spec", within_spec},
                      {"local_size", args.local_size},
                      {"subgroup_size", wg::SubgroupSize()},
                      {"schedule", ToString(wg::GetSchedule())},
                      {"workgroup_model", emu::WorkgroupModel()},
                      {"workgroup_checker", checker},
                      {"split_dispatches", gpu.extra_dispatches(gpu)},
                      {"paged_arrays", gpu.paged_arrays(gpu)},
                      {"passes", passes},
                      {"calls", calls},
                      {"host_only", {"prep (bounding spheres: per-scene preprocessing)", "rah ray order (a stable partition by light)",
                                     args.algo == "brute" || args.algo == "embree" ? "trace (host tracer)" : "hierarchy groups (CSR offsets)"}},
                      {"equal", equal},
                      {"stopped", stopped.empty() ? nlohmann::json(nullptr) : nlohmann::json(stopped)},
                      {"first_divergent_pass", first ? nlohmann::json(first->pass) : nlohmann::json(nullptr)},
                      {"digest", equal && within_spec == 0 ? nlohmann::json(HexDigest(frame.digest.Frame())) : nlohmann::json(nullptr)}};
  std::ofstream f(args.report);
  if (!f) ThrowInput("{}: cannot write the report", args.report);
  f << j.dump(2) << "\n";
}

// A planted fault in a frame that compared equal. A kernel-side fault the device ran without a visible
// effect (a race that came out right, a divergent barrier its SIMD code reaches anyway) is not a
// pass: say so. An emulator-side one may sit in a pass the frame did not run (traverse.compact's,
// which only --path fused runs).
void PrintUnseenFault(const DiffArgs& args, const Injection& injection, std::size_t within_spec) {
  if (!injection.kernel.empty() && within_spec)
    std::printf("  planted fault %s: seen, and every difference is within the spec's precision\n", args.inject.c_str());
  else if (!injection.kernel.empty())
    std::printf("  planted fault %s: not seen, the device executed it benignly (local size %d, subgroup size %u)\n",
                args.inject.c_str(), args.local_size, wg::SubgroupSize());
  else if (!injection.emu.empty())
    std::printf("  planted fault %s: not seen, its emulated pass did not run or the fault changed nothing\n", args.inject.c_str());
}

// The fused path's traverse.compact, for the workgroups line: it runs on the workgroup model only
// when the run asks for it.
const char* CompactEmulation(const DiffArgs& args, bool hierarchy) {
  if (!hierarchy || args.path != "fused") return "";
  return emu::RunsWorkgroupMirror("traverse.compact") ? "; traverse.compact on its workgroup mirror" : "; traverse.compact on SIMD lanes";
}

}  // namespace

ExitCode RunDiff(const DiffArgs& args) {
  emu::FrameOptions fo;
  const Scene scene = LoadSceneForFrame(args.scene, args.data, args.size, fo.width, fo.height);
  const Injection injection = ParseInject(args.inject);
  const Backend gpu = MakeBackend("vulkan", args.device, args.local_size, injection.kernel, args.Limits(), args.kernels);
  ConfigureEmulatedKernels(args.model, static_cast<std::uint32_t>(args.local_size), gpu.subgroup_size, injection);
  const SceneBuffers buffers = FlattenScene(scene);
  CheckFrameFits(gpu, fo.width, fo.height, scene.lights.size(), buffers.triangles.size());
  auto direct = emu::MakeDirectTracer(buffers, emu::DirectMode::kAuto);

  verify::Backends expected{emu::EmuFramePasses(), emu::EmuHierarchyPasses()};
  verify::Backends actual{gpu.Frame(), gpu.Hierarchy()};
  const bool relaxed = args.compare == "relaxed" || (args.compare == "auto" && !gpu.correctly_rounded);
  verify::Differ differ(expected, actual, {args.save_inputs, direct.get(), args.inject, relaxed});
  fo.passes = &differ.frame();

  // The frame's tracer: a hierarchy whose passes go through the Differ, or a host tracer (brute,
  // embree) whose traces are not GPU passes.
  std::unique_ptr<Tracer> host_tracer;
  std::unique_ptr<emu::HierarchyTracer> hierarchy;
  if (args.algo == "brute") {
    host_tracer = emu::MakeDirectTracer(buffers, emu::DirectMode::kAuto);
  } else if (args.algo == "embree") {
    host_tracer = refs::MakeEmbreeTracer(buffers, 0);
  } else {
    emu::HierarchyConfig cfg = MakeHierarchyConfig(args, fo.width, fo.height, &differ.hierarchy());
    cfg.fused = args.path == "fused";
    hierarchy = emu::MakeHierarchyTracer(buffers, cfg);
  }
  Tracer& tracer = hierarchy ? static_cast<Tracer&>(*hierarchy) : *host_tracer;

  std::printf("rayspace diff: %s (%dx%d, %s) on %s\n  emulation model: %s\n", scene.name.c_str(), fo.width, fo.height,
              args.algo.c_str(), gpu.device.c_str(), EmulationModel().c_str());
  std::printf("  workgroups: local size %d, subgroup size %u, schedule %s, checker %s%s\n", args.local_size,
              wg::SubgroupSize(), ToString(wg::GetSchedule()).c_str(), wg::Checking() ? "on" : "off", CompactEmulation(args, hierarchy != nullptr));
  std::printf("  comparison: %s\n", relaxed ? "relaxed (what a conformant device may compute; docs/numerics.md)"
                                             : "bitwise");
  std::string stopped;
  nlohmann::json checker = nullptr;  // the workgroup checker's reports, when it stopped the frame
  emu::FrameResult frame;
  try {
    frame = emu::RenderFrame(scene, buffers, tracer, fo);
  } catch (const verify::DiffStop& stop) {
    stopped = stop.what();
  } catch (const wg::CheckError& e) {
    checker = PrintCheckerReports(e.result);
    stopped = "the emulator's workgroup checker stopped the frame in " + checker["pass"].get<std::string>();
  }

  // Totals per kernel pass, in order of first appearance.
  DiffTotals totals = Totals(differ.calls());
  const verify::CallRecord* first = totals.first;
  const nlohmann::json passes = PrintPasses(totals);
  PrintWithinSpec(totals);
  PrintFirstDivergence(first);
  if (!stopped.empty()) std::printf("  stopped: %s\n", stopped.c_str());
  const bool equal = first == nullptr && stopped.empty();
  if (equal && totals.within_spec)
    std::printf("  all passes equal or within the spec's precision\n");
  else if (equal)
    std::printf("  all passes equal\n");
  else if (first)
    std::printf("  first divergent pass: %s\n", first->pass.c_str());
  else
    std::printf("  no pass compared unequal before the stop\n");
  if (equal && totals.within_spec == 0) std::printf("  frame digest %s\n", HexDigest(frame.digest.Frame()).c_str());
  if (equal) PrintUnseenFault(args, injection, totals.within_spec);
  std::printf("  vulkan: %zu split dispatches, %zu arrays paged over several bindings\n", gpu.extra_dispatches(gpu),
              gpu.paged_arrays(gpu));
  if (!args.report.empty())
    WriteDiffReport(args, scene, fo, gpu, differ, passes, equal, stopped, first, frame, checker, relaxed, totals.within_spec);
  if (!checker.is_null()) return ExitCode::kWorkgroupFault;
  return equal ? ExitCode::kOk : ExitCode::kDivergence;
}

// The comparison.json a diff saved beside a call's inputs, checked; nothing when there is none.
std::optional<nlohmann::json> ReadRecorded(const std::string& path) {
  if (std::error_code ec; !std::filesystem::exists(path, ec)) return std::nullopt;
  nlohmann::json recorded;
  try {
    recorded = nlohmann::json::parse(ReadInputFile(path, {"recorded comparison", kMaxTextFileBytes}));
  } catch (const nlohmann::json::exception&) {
    ThrowInput("{}: not valid JSON", path);
  }
  CheckRecorded(recorded, path);
  return recorded;
}

ExitCode RunReplay(const ReplayArgs& args) {
  std::string method_name;
  const verify::BufferSet in = verify::BufferSet::Load(args.dir, method_name);
  const verify::PassMethod& method = verify::FindPassMethod(method_name);
  CheckSavedInputs(in, args.dir);
  // The comparison the diff recorded when it saved these inputs, if present: same answer expected.
  const std::optional<nlohmann::json> saved = ReadRecorded(args.dir + "/comparison.json");
  const Injection injection = ParseInject(args.inject);
  const Backend gpu = MakeBackend("vulkan", args.device, args.local_size, injection.kernel, {args.split_bytes, args.max_groups}, args.kernels);
  ConfigureEmulatedKernels(args.model, static_cast<std::uint32_t>(args.local_size), gpu.subgroup_size, injection);
  verify::Backends expected{emu::EmuFramePasses(), emu::EmuHierarchyPasses()};
  verify::Backends actual{gpu.Frame(), gpu.Hierarchy()};
  verify::BufferSet out;
  std::printf("rayspace replay: %s (%s) on %s\n", method.pass(in).c_str(), method_name.c_str(), gpu.device.c_str());
  verify::CallRecord r;
  try {
    const bool relaxed = args.compare == "relaxed" || (args.compare == "auto" && !gpu.correctly_rounded);
    r = verify::RunAndCompare(method, in, expected, actual, out, nullptr, relaxed);
  } catch (const wg::CheckError& e) {
    PrintCheckerReports(e.result);
    return ExitCode::kWorkgroupFault;
  }
  if (!r.error.empty()) std::printf("  vulkan backend failed: %s\n", r.error.c_str());
  for (const BufferComparison& b : r.buffers) std::printf("  %s\n", b.Summary().c_str());
  if (!r.spec.empty()) std::printf("  relaxed model: %s\n", r.spec.c_str());
  if (!r.raster.empty()) std::printf("  raster: %s\n", r.raster.c_str());
  if (!r.equal && r.within_spec) std::printf("  every difference is within the spec's precision\n");
  if (saved) {
    const nlohmann::json& recorded = *saved;
    bool same = recorded.value("equal", !r.equal) == r.equal && recorded.contains("buffers") &&
                recorded["buffers"].size() == r.buffers.size();
    if (same) {
      for (std::size_t i = 0; i < r.buffers.size(); ++i) {
        nlohmann::json now;
        r.buffers[i].ToJson(now);
        now["pass"] = recorded["buffers"][i].value("pass", now["pass"].get<std::string>());
        same &= now == recorded["buffers"][i];
      }
    }
    std::printf("  recorded comparison: %s\n", same ? "reproduced" : "NOT reproduced");
    const std::string rec_inject = recorded.value("inject", std::string());
    if (!same && rec_inject != args.inject)
      std::printf("  (recorded with --inject '%s', replayed with '%s')\n", rec_inject.c_str(), args.inject.c_str());
    if (!same) return ExitCode::kNotReproduced;
  }
  std::printf("  %s\n", r.equal ? "equal" : (r.within_spec ? "within the spec's precision" : "divergent"));
  if (!args.report.empty()) {
    nlohmann::json j = CallJson(r);
    j["dir"] = args.dir;
    std::ofstream f(args.report);
    if (!f) ThrowInput("{}: cannot write the report", args.report);
    f << j.dump(2) << "\n";
  }
  return r.equal || r.within_spec ? ExitCode::kOk : ExitCode::kDivergence;
}

}  // namespace rayspace::app
