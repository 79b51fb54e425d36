#include "rayspace/diff/diff_command.h"
#include "rayspace/frame/version.h"
#include "rayspace/frame/backend_setup.h"
#include "rayspace/diff/coverage_options.h"
#include "rayspace/frame/command_util.h"
#include "rayspace/diff/diff_impact.h"
#include "rayspace/diff/junit_reports.h"
#include "rayspace/frame/kernel_model.h"
#include "rayspace/frame/memory_estimate.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>

#include <unistd.h>


#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "rayspace/emu/frame.h"
#include "rayspace/emu/hierarchy.h"
#include "rayspace/emu/grid/tracer.h"
#include "rayspace/emu/tl/tracer.h"
#include "rayspace/emu/output_checks.h"
#include "rayspace/emu/workgroup_ops.h"
#include "rayspace/error.h"
#include "rayspace/input_file.h"
#include "rayspace/gpu/passes.h"
#include "rayspace/json_text.h"
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
  if (!c.pairs.empty()) j["pairs"] = c.pairs;
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
  bool failed = false;  // a call of the pass failed on a backend: compared nothing
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
    if (c.error_device_fault) {  // the device could not finish the call: nothing compared, not a divergence
      t.failed = true;
      continue;
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
nlohmann::json PrintPasses(DiffTotals& d, const std::string& expected, const std::string& actual) {
  nlohmann::json passes = nlohmann::json::array();
  std::printf("  %-18s %6s %12s %11s %11s  %s\n", "pass", "calls", "mismatches", (expected + " ms").c_str(), (actual + " ms").c_str(),
              "buffers (elements)");
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
    std::printf("  %-18s %6zu %12zu %11.1f %11.1f  %s%s\n", p.c_str(), t.calls, mism, t.emu_ms, t.vulkan_ms, bufs.c_str(),
                t.failed ? (bufs.empty() ? "failed on a backend" : "; a call failed on a backend") : "");
    nlohmann::json pj = {{"pass", p}, {"calls", t.calls}, {"equal", t.equal && !t.failed}, {"failed", t.failed}, {"buffers", bj}, {"max_ulp", t.max_ulp},
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
    std::fprintf(stderr, "  first divergence: %s at %s (call %zu)\n", first->pass.c_str(), first->label.c_str(), first->seq);
    if (!first->error.empty()) std::fprintf(stderr, "    %s\n", first->error.c_str());
    for (const BufferComparison& b : first->buffers)
      if (!b.Equal()) std::fprintf(stderr, "    %s\n", b.Summary().c_str());
    if (!first->hits.empty()) std::fprintf(stderr, "    hits: %s\n", first->hits.c_str());
    if (!first->pairs.empty()) std::fprintf(stderr, "    pairs: %s\n", first->pairs.c_str());
    if (!first->raster.empty()) std::fprintf(stderr, "    raster: %s\n", first->raster.c_str());
    if (!first->spec.empty()) std::fprintf(stderr, "    relaxed model: %s\n", first->spec.c_str());
  }
}

// The workgroup checker's reports (an emulated kernel raced, read an unwritten shared word or hit a
// divergent barrier) on stderr, at most 10 lines, and as the report's "workgroup_checker".
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
  std::fprintf(stderr, "  workgroup checker: %zu report(s) in %s (pass %s): %s\n", r.reports.size() + r.dropped, dispatch.c_str(),
              j["pass"].get<std::string>().c_str(), kinds.c_str());
  for (std::size_t k = 0; k < ordered.size(); ++k) {
    const wg::Report& rep = *ordered[k];
    if (k < 10) std::fprintf(stderr, "    %s\n", rep.message.c_str());
    j["reports"].push_back({{"kind", wg::ToString(rep.kind)}, {"workgroup", rep.workgroup}, {"phase", rep.phase},
                            {"array", rep.array}, {"word", rep.word}, {"invocations", {rep.inv_a, rep.inv_b}},
                            {"message", rep.message}});
  }
  return j;
}

// What the diff's frame came to.
struct DiffOutcome {
  emu::FrameResult frame;
  std::string stopped;              // why the frame stopped early, or ""
  nlohmann::json checker = nullptr; // the workgroup checker's reports, when it stopped the frame
  // The simulated device's checker finding on a kernel (racecheck, initcheck, synccheck, memcheck)
  // that stopped the frame: {"checker", "pass", "finding"}.
  nlohmann::json sim_checker = nullptr;
  // A backend's failure on a pass that no checker owns (a device error, the simulated GPU's step
  // limit): {"pass", "error"}. Nothing was compared from that pass on: a fault, not a divergence.
  nlohmann::json backend_fault = nullptr;
};

// A simulated device's checker finding on a pass's kernel, from the backend's error: {"checker",
// "pass", "finding"} (the finding as the simulator words it, from the kernel's name on). diff and
// replay report it alike.
nlohmann::json SimCheckerJson(const std::string& checker, const std::string& pass, const std::string& finding) {
  return {{"checker", checker}, {"pass", pass}, {"finding", finding}};
}
void PrintSimChecker(const nlohmann::json& f) {
  std::fprintf(stderr, "  %s on the kernel of %s: %s\n", f["checker"].get<std::string>().c_str(), f["pass"].get<std::string>().c_str(),
               f["finding"].get<std::string>().c_str());
}

// The --report file: the run, every pass's totals and every call.
nlohmann::json DiffReport(const DiffArgs& args, const Scene& scene, const emu::FrameOptions& fo, const Backend& gpu,
                          const verify::Differ& differ, const nlohmann::json& passes, bool equal, const DiffOutcome& run,
                          const verify::CallRecord* first, bool relaxed, std::size_t within_spec) {
  nlohmann::json calls = nlohmann::json::array();
  for (const verify::CallRecord& c : differ.calls()) calls.push_back(CallJson(c));
  return {{"scene", scene.name},
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
          {"workgroup_checker", run.checker},
          {"split_dispatches", gpu.extra_dispatches(gpu)},
          {"paged_arrays", gpu.paged_arrays(gpu)},
          {"passes", passes},
          {"calls", calls},
          {"host_only", {"prep (bounding spheres: per-scene preprocessing)", "rah ray order (a stable partition by light)",
                         args.algo == "brute" || args.algo == "embree" ? "trace (host tracer)"
                         : args.algo == "tl"                            ? "tl tree (the bounding-sphere tree and shared vertices)"
                         : args.algo == "grid"                          ? "grid build (the perspective and regular grids)"
                                                                        : "hierarchy groups (CSR offsets)"}},
          {"equal", equal},
          {"stopped", run.stopped.empty() ? nlohmann::json(nullptr) : nlohmann::json(run.stopped)},
          {"first_divergent_pass", first ? nlohmann::json(first->pass) : nlohmann::json(nullptr)},
          {"saved_inputs", args.save_inputs.empty() ? nlohmann::json(nullptr) : nlohmann::json(args.save_inputs)},
          {"digest", equal && within_spec == 0 ? nlohmann::json(HexDigest(run.frame.digest.Frame())) : nlohmann::json(nullptr)}};
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

// Every option of a diff (or a replay) that changes what a pass call computes or how it is compared,
// recorded beside each saved call so that `replay` reruns the call as the diff ran it.
template <typename Args>
nlohmann::json RecordedOptions(const Args& args, const Backend& gpu) {
  nlohmann::json kernels = nlohmann::json::array();
  for (const std::string& k : args.kernels) {  // PASS=FILE with FILE made absolute: replay may run elsewhere
    const auto eq = k.find('=');
    kernels.push_back(eq == std::string::npos ? k : k.substr(0, eq + 1) + std::filesystem::absolute(k.substr(eq + 1)).string());
  }
  return {{"split_bytes", args.split_bytes},   {"max_groups", args.max_groups},
          {"local_size", args.local_size},     {"inject", args.inject},
          {"compare", args.compare},           {"schedule", args.model.schedule},
          {"check_workgroups", args.model.check}, {"strict_math", vk::Context::StrictMath()},
          {"kernels", kernels},                {"device", gpu.device}};
}

// --save-inputs: a new or empty directory, so that the calls of different runs never mix, in which a
// file can be created.
// The directory the saved calls go into, watched until the diff's verdict: an error or a signal
// (SIGTERM, SIGINT, ...) before it leaves the directory as it was found (gone, or empty), never
// half-filled. Null without --save-inputs.
std::unique_ptr<TempDirectory> PrepareSaveDir(const std::string& dir) {
  namespace fs = std::filesystem;
  if (dir.empty()) return nullptr;
  std::error_code ec;
  const fs::file_status st = fs::status(dir, ec);
  if (fs::exists(st) && !fs::is_directory(st)) ThrowInput("--save-inputs {}: not a directory", dir);
  if (fs::exists(st)) {
    const bool empty = fs::is_empty(dir, ec);
    if (ec) ThrowInput("--save-inputs {}: cannot read the directory ({})", dir, ec.message());
    if (!empty)
      ThrowInput("--save-inputs {}: the directory is not empty; give a new or empty one, so that the saved calls of "
                 "different runs do not mix", dir);
  }
  CheckOutputParent(dir, "--save-inputs");
  // Made here (or, found empty, adopted) and removed or emptied again unless the diff completes.
  std::unique_ptr<TempDirectory> saving;
  try {
    saving = std::make_unique<TempDirectory>(dir, fs::exists(st));
  } catch (const InputError& e) {
    ThrowInput("--save-inputs {}", e.what());
  }
  OpenOutput(dir + "/pass.json", "the saved inputs", nullptr, false);  // writable: its temporary file goes again
  return saving;
}

// The frame's tracer: a hierarchy whose passes go through the Differ, or a host tracer (brute,
// embree) whose traces are not GPU passes.
struct DiffTracer {
  std::unique_ptr<Tracer> host;
  std::unique_ptr<emu::HierarchyTracer> hierarchy;
  std::unique_ptr<emu::TlTracer> tl;      // --algo tl: its passes go through the Differ too
  std::unique_ptr<emu::GridTracer> grid;  // --algo grid: likewise
  Tracer& get() {
    if (hierarchy) return *hierarchy;
    if (tl) return *tl;
    if (grid) return *grid;
    return *host;
  }
};

// The actual side of --backends ("emu,vulkan", "emu,sim" or "sim,vulkan"). Not given: a Vulkan
// device, or the simulated GPU where no Vulkan device is usable (said on stderr).
Backend MakeActualBackend(const std::string& backends, bool given, int device, int local_size,
                          const std::map<std::string, std::uint32_t>& faults, const TestLimits& limits, const KernelFiles& kernels,
                          std::uint32_t subgroup_size = 0, const std::string& schedule = "forward", const std::string& sim_checks = "",
                          const std::string& device_model = "", const std::string& subgroup_layout = "", std::uint64_t step_limit = 0) {
  const std::string actual = backends.substr(backends.find(',') + 1);
  const sim::DeviceConfig simulated =
      SimulatedConfig(backends, subgroup_size, schedule, sim_checks, device_model, subgroup_layout, step_limit);
  if (given || actual != "vulkan") return MakeBackend(actual, device, local_size, faults, limits, kernels, simulated);
  try {
    return MakeBackend("vulkan", device, local_size, faults, limits, kernels);
  } catch (const std::runtime_error& e) {
    // No device, or no driver at all (the loader finds no ICD: vkCreateInstance's INCOMPATIBLE_DRIVER).
    const std::string why = e.what();
    if (why.find("no Vulkan device found") == std::string::npos && why.find("VK_ERROR_INCOMPATIBLE_DRIVER") == std::string::npos) throw;
    std::fprintf(stderr, "rayspace: no Vulkan device: the kernels run on the simulated GPU (--backends emu,sim)\n");
    return MakeBackend("sim", device, local_size, faults, limits, kernels);
  }
}

DiffTracer MakeDiffTracer(const DiffArgs& args, const SceneBuffers& buffers, const emu::FrameOptions& fo, emu::HierarchyPasses& passes,
                          std::vector<std::uint64_t>* candidate_log = nullptr) {
  DiffTracer t;
  if (args.algo == "brute") {
    t.host = emu::MakeDirectTracer(buffers, emu::DirectMode::kAuto);
  } else if (args.algo == "embree") {
    t.host = refs::MakeEmbreeTracer(buffers, 0);
  } else if (args.algo == "tl") {
    t.tl = emu::MakeTlTracer(buffers, MakeTlOptions(args), &passes);
  } else if (args.algo == "grid") {
    t.grid = emu::MakeGridTracer(buffers, MakeGridOptions(args), &passes);
  } else {
    emu::HierarchyConfig cfg = MakeHierarchyConfig(args, fo.width, fo.height, &passes);
    cfg.fused = args.path == "fused";
    cfg.candidate_log = candidate_log;
    t.hierarchy = emu::MakeHierarchyTracer(buffers, cfg);
  }
  return t;
}

DiffOutcome RunDiffFrame(const Scene& scene, const SceneBuffers& buffers, Tracer& tracer, const emu::FrameOptions& fo) {
  DiffOutcome run;
  try {
    run.frame = emu::RenderFrame(scene, buffers, tracer, fo);
  } catch (const verify::DiffStop& stop) {
    run.stopped = stop.what();
    if (!stop.checker().empty()) run.sim_checker = SimCheckerJson(stop.checker(), stop.pass(), stop.finding());
    else if (stop.device_fault()) run.backend_fault = {{"pass", stop.pass()}, {"error", stop.what()}};
  } catch (const emu::DeviceOutputError& e) {
    // The Differ compared the call's outputs before the host checked them: the pass is reported.
    run.stopped = std::string("device output error: ") + e.what();
  } catch (const wg::CheckError& e) {
    run.checker = PrintCheckerReports(e.result);
    run.stopped = "the emulator's workgroup checker stopped the frame in " + run.checker["pass"].get<std::string>();
  }
  return run;
}

void PrintDiffHeader(const DiffArgs& args, const Scene& scene, const emu::FrameOptions& fo, const Backend& gpu, bool relaxed,
                     bool hierarchy) {
  std::printf("rayspace diff: %s (%dx%d, %s) on %s\n  emulation model: %s\n", scene.name.c_str(), fo.width, fo.height,
              args.algo.c_str(), gpu.device.c_str(), EmulationModel().c_str());
  std::printf("  workgroups: local size %d, subgroup size %u, schedule %s, checker %s%s\n", args.local_size,
              wg::SubgroupSize(), ToString(wg::GetSchedule()).c_str(), wg::Checking() ? "on" : "off", CompactEmulation(args, hierarchy));
  std::printf("  comparison: %s\n", relaxed ? "relaxed (what a conformant device may compute; docs/numerics.md)" : "bitwise");
}

// Why the planted fault could not fire in this frame, or "" (also when the frame stopped early: the
// passes after the stop did not get their chance).
std::string DiffFaultCannotFire(const DiffArgs& args, const Injection& injection, const verify::Differ& differ,
                                const Backend& gpu, const DiffOutcome& run) {
  if (args.inject.empty() || !run.stopped.empty()) return {};
  FaultFacts facts;
  for (const verify::CallRecord& c : differ.calls()) facts.passes.insert(c.pass);
  facts.split = gpu.extra_dispatches(gpu) + gpu.paged_arrays(gpu) > 0;
  facts.rows = gpu.folded_launches(gpu) > 0;
  facts.scan = args.reduction == "scan";
  return FaultCannotFire(args.inject, injection, facts);
}

// The verdict: on stdout when every pass is equal; on stderr, with the first divergence, otherwise.
void PrintDiffVerdict(const DiffArgs& args, const Injection& injection, const DiffTotals& totals, const DiffOutcome& run,
                      bool equal) {
  PrintWithinSpec(totals);
  if (equal && totals.within_spec)
    std::printf("  all passes equal or within the spec's precision\n");
  else if (equal)
    std::printf("  all passes equal\n");
  else if (totals.first)
    std::fprintf(stderr, "rayspace diff: first divergent pass: %s\n", totals.first->pass.c_str());
  else if (!run.backend_fault.is_null())
    std::fprintf(stderr, "rayspace diff: the actual backend failed at pass %s; nothing was compared from there\n",
                 run.backend_fault["pass"].get<std::string>().c_str());
  else
    std::fprintf(stderr, "rayspace diff: no pass compared unequal before the stop\n");
  PrintFirstDivergence(totals.first);
  if (!run.stopped.empty()) std::fprintf(stderr, "  stopped: %s\n", run.stopped.c_str());
  if (equal && totals.within_spec == 0) std::printf("  frame digest %s\n", HexDigest(run.frame.digest.Frame()).c_str());
  if (equal) PrintUnseenFault(args, injection, totals.within_spec);
}

void PrintSavedInputs(const DiffArgs& args, const verify::Differ& differ) {
  if (args.save_inputs.empty()) return;
  std::size_t saved = 0;
  for (const verify::CallRecord& c : differ.calls()) saved += !c.saved.empty();
  std::printf("  inputs saved: %zu call%s in %s (rayspace replay %s/NNNN-PASS)\n", saved, saved == 1 ? "" : "s",
              args.save_inputs.c_str(), args.save_inputs.c_str());
}

// After a divergence, what it does to the picture: the frame on each backend alone, compared (null when
// the diff found none, or the workgroup checker stopped it before any comparison mattered).
nlohmann::json MeasureDiffImpact(const DiffArgs& args, const Scene& scene, const SceneBuffers& buffers, const emu::FrameOptions& fo,
                                 const Backend& gpu, const DiffTotals& totals, const DiffOutcome& run) {
  if (!totals.first || !run.checker.is_null() || !run.sim_checker.is_null()) return nullptr;
  if (args.no_impact) {
    std::fprintf(stderr, "  impact: not measured (--no-impact)\n");
    return {{"measured", false}, {"skipped", "--no-impact"}};
  }
  const ImpactTracerFactory make = [&](emu::HierarchyPasses& passes, std::vector<std::uint64_t>* candidate_log) -> std::unique_ptr<Tracer> {
    DiffTracer t = MakeDiffTracer(args, buffers, fo, passes, candidate_log);
    if (t.hierarchy) return std::move(t.hierarchy);
    if (t.tl) return std::move(t.tl);
    if (t.grid) return std::move(t.grid);
    return std::move(t.host);
  };
  DiffImpact impact = MeasureImpact(scene, buffers, fo, make, {&emu::EmuFramePasses(), &emu::EmuHierarchyPasses()},
                                    {&gpu.Frame(), &gpu.Hierarchy()});
  if (!totals.first->pairs.empty()) impact.differed.push_back("candidate pairs: " + totals.first->pairs);
  for (const BufferComparison& b : totals.first->buffers)
    if (!b.Equal()) impact.differed.push_back(b.Summary());
  PrintImpact(stderr, impact);
  return ImpactJson(impact);
}

// One frame of a diff with args.inject planted, on a device made once: the planted fault set on both
// sides, the frame compared call by call, the verdict printed, and the report with the impact.
struct FaultRun {
  ExitCode verdict = ExitCode::kOk;
  nlohmann::json report;
};
FaultRun DiffFrame(const DiffArgs& args, const Scene& scene, SceneBuffers& buffers, emu::FrameOptions fo, const Backend& gpu,
                   const MemoryEstimate& estimate, const Backend* reference) {
  const Injection injection = ParseInject(args.inject);
  if (gpu.set_faults) gpu.set_faults(gpu, injection.kernel);
  const ScopedSettings model = EmulatedKernels(args.model, static_cast<std::uint32_t>(args.local_size), gpu.subgroup_size, injection);
  auto direct = emu::MakeDirectTracer(buffers, emu::DirectMode::kAuto);

  // The expected side: the emulator, or (--backends sim,vulkan) the kernels on the simulated GPU.
  verify::Backends expected = reference ? verify::Backends{reference->Frame(), reference->Hierarchy()}
                                        : verify::Backends{emu::EmuFramePasses(), emu::EmuHierarchyPasses()};
  verify::Backends actual{gpu.Frame(), gpu.Hierarchy()};
  const bool relaxed = args.compare == "relaxed" || (args.compare == "auto" && !gpu.correctly_rounded);
  verify::Differ differ(expected, actual, {args.save_inputs, direct.get(), args.inject, relaxed, RecordedOptions(args, gpu)});
  fo.passes = &differ.frame();
  DiffTracer tracer = MakeDiffTracer(args, buffers, fo, differ.hierarchy());
  PrintDiffHeader(args, scene, fo, gpu, relaxed, tracer.hierarchy != nullptr);
  if (reference) std::printf("  expected side: %s, the same kernels\n", reference->device.c_str());
  const DiffOutcome run = RunDiffFrame(scene, buffers, tracer.get(), fo);
  // Before the verdict: a kernel that never ran, or a fault that could not fire, leaves none. A frame
  // stopped early (a divergence, a checker's finding) has its verdict, and the passes after the stop
  // could not launch.
  if (run.stopped.empty()) CheckKernelsRan(gpu, args.kernels);
  if (const std::string why = DiffFaultCannotFire(args, injection, differ, gpu, run); !why.empty()) ThrowInput("{}", why);

  DiffTotals totals = Totals(differ.calls());
  const nlohmann::json passes = PrintPasses(totals, reference ? reference->name : "emu", gpu.name);
  const bool equal = totals.first == nullptr && run.stopped.empty();
  PrintDiffVerdict(args, injection, totals, run, equal);
  std::printf("  %s: %zu split dispatches, %zu arrays paged over several bindings\n", gpu.name.c_str(), gpu.extra_dispatches(gpu),
              gpu.paged_arrays(gpu));
  PrintSavedInputs(args, differ);
  const nlohmann::json coverage = ReportKernelCoverage(reference ? *reference : gpu, args.kernels);
  // The report is made before the impact's frames add to the device's dispatch counts.
  FaultRun r;
  r.report = DiffReport(args, scene, fo, gpu, differ, passes, equal, run, totals.first, relaxed, totals.within_spec);
  r.report["kernel_coverage"] = coverage;
  if (args.coverage_options)
    r.report["coverage_options"] =
        ProbeCoverageOptions({args.scene, args.data, "16x16", args.kernels, 120}, coverage);
  r.report["memory_estimate"] = MemoryEstimateJson(estimate);
  if (reference && totals.first && run.checker.is_null() && run.sim_checker.is_null()) {
    // The impact renders the frame on the emulator and on the actual device: a third side.
    std::fprintf(stderr, "  impact: not measured (the expected side is the simulated GPU; the impact compares with the emulator)\n");
    r.report["impact"] = {{"measured", false}, {"skipped", "--backends sim,vulkan"}};
  } else {
    r.report["impact"] = MeasureDiffImpact(args, scene, buffers, fo, gpu, totals, run);
  }
  if (reference) r.report["expected_device"] = reference->device;
  if (!run.sim_checker.is_null()) {
    r.report["simulator_checker"] = run.sim_checker;
    PrintSimChecker(run.sim_checker);
  }
  if (!run.backend_fault.is_null()) r.report["backend_fault"] = run.backend_fault;
  r.verdict = !run.checker.is_null() || !run.sim_checker.is_null() ? ExitCode::kWorkgroupFault
              : totals.first                                       ? ExitCode::kDivergence
              : !run.backend_fault.is_null()                       ? ExitCode::kBackendFault
              : equal                                              ? ExitCode::kOk
                                                                   : ExitCode::kDivergence;
  return r;
}

// --backends sim,vulkan: both sides run the kernels, so a planted fault would be in both or in one by
// a choice the user did not make, and the relaxed model judges a device against the emulator's bits.
void CheckDevicePair(const DiffArgs& args) {
  if (args.backends != "sim,vulkan") return;
  if (!args.inject.empty() || !args.inject_each.empty())
    ThrowInput("--inject with --backends sim,vulkan: plant faults against the emulator (--backends emu,sim or emu,vulkan)");
  if (args.compare == "relaxed")
    ThrowInput("--compare relaxed with --backends sim,vulkan: the relaxed model judges a device against the emulator; use "
               "--backends emu,vulkan");
}

// --inject-each: every value a fault diff accepts, and nothing that saves one frame's calls.
void CheckInjectEach(const DiffArgs& args) {
  if (args.inject_each.empty()) return;
  if (!args.inject.empty()) ThrowInput("--inject-each: give --inject or --inject-each, not both");
  if (!args.save_inputs.empty())
    ThrowInput("--inject-each: --save-inputs saves the calls of one frame; plant one fault with --inject");
  for (const std::string& f : args.inject_each) {
    if (f.empty()) ThrowInput("--inject-each: an empty fault in the list");
    try {
      ParseInject(f);
    } catch (const InputError& e) {
      const std::string m = e.what();  // "--inject 'F': why"
      ThrowInput("--inject-each{}", m.rfind("--inject", 0) == 0 ? m.substr(8) : ": " + m);
    }
  }
}

}  // namespace

DiffResult DiffToReport(const DiffArgs& args, const std::function<void(const Scene&)>& on_scene) {
  CheckInjectEach(args);
  CheckDevicePair(args);
  // Coverage is the simulated GPU's, of a user's kernel: without both there is nothing to probe.
  if (args.coverage_options && (args.backends != "emu,sim" || args.kernels.empty()))
    ThrowInput("--coverage-options: probes the lines of a --kernel the simulated GPU never reached; give --backends emu,sim and --kernel "
               "PASS=FILE");
  const bool one_sided = OneSided(args);
  emu::FrameOptions fo;
  const Scene scene = LoadSceneForFrame(args.scene, args.data, args.size, fo.width, fo.height, args.bounces);
  fo.progress = args.progress || isatty(STDERR_FILENO);  // progress on stderr when someone watches
  ApplyFaithful(args.faithful, fo);
  ApplyPrimary(args, fo);
  const Injection injection = ParseInject(args.inject_each.empty() ? args.inject : args.inject_each.front());
  if (on_scene) on_scene(scene);  // before the frame, as --save-inputs
  const MemoryUse use{.copies = kDiffCopies,
                      .slot_copies = args.Hierarchy() && args.path == "passes" ? kDiffSlotCopies : 0,
                      .subdivision = args.subdivision,
                      .pair_capacity = args.pair_capacity,
                      .levels = args.depth_auto ? 0 : args.depth,
                      .object_mask = args.algo == "crsh",
                      .object_tree = args.Hierarchy() && args.objects != "flat"};
  const MemoryEstimate estimate = EstimateFrameMemory(scene, fo.width, fo.height, use);
  CheckFitsMachine(estimate, fo.width, fo.height, SizeFrom(args.size, scene).c_str(), "the diff");
  const Backend gpu = MakeActualBackend(args.backends, args.backends_given, args.device, args.local_size, injection.kernel, args.Limits(),
                                        args.kernels, args.subgroup_size, args.model.schedule, args.sim_checks, args.device_model,
                                        args.subgroup_layout, args.step_limit);
  // --backends sim,vulkan: the kernels on the simulated GPU are the expected side.
  std::optional<Backend> reference;
  if (args.backends == "sim,vulkan")
    reference = MakeBackend("sim", args.device, args.local_size, {}, args.Limits(), args.kernels,
                            SimulatedConfig(args.backends, args.subgroup_size, args.model.schedule, args.sim_checks, args.device_model,
                                            args.subgroup_layout, args.step_limit));
  const ScopedSettings model = EmulatedKernels(args.model, static_cast<std::uint32_t>(args.local_size), gpu.subgroup_size, injection);
  SceneBuffers buffers = FlattenForFrame(scene, args.faithful);
  buffers.one_sided = one_sided;
  CheckFrameFits(gpu, fo.width, fo.height, ShadowSlotsPerSurface(scene.lights), buffers.triangles.size(), SizeFrom(args.size, scene));
  if (args.algo == "grid") CheckGridBuild(gpu);
  const std::unique_ptr<TempDirectory> saving = PrepareSaveDir(args.save_inputs);  // last: it creates the directory

  nlohmann::json j;
  ExitCode verdict = ExitCode::kOk;
  if (args.inject_each.empty()) {
    FaultRun r = DiffFrame(args, scene, buffers, fo, gpu, estimate, reference ? &*reference : nullptr);
    j = std::move(r.report);
    verdict = r.verdict;
  } else {
    // A frame per fault on the one device: only the faulted kernels' pipelines are made again.
    j = {{"faults", nlohmann::json::array()}};
    for (std::size_t i = 0; i < args.inject_each.size(); ++i) {
      DiffArgs one = args;
      one.inject = args.inject_each[i];
      one.inject_each.clear();
      std::printf("rayspace diff: planted fault %s (%zu of %zu)\n", one.inject.c_str(), i + 1, args.inject_each.size());
      FaultRun r = DiffFrame(one, scene, buffers, fo, gpu, estimate, reference ? &*reference : nullptr);
      j["faults"].push_back(std::move(r.report));
      // A frame the workgroup checker stopped outranks a divergence, which outranks a backend's
      // failure, which outranks equality.
      const auto rank = [](ExitCode c) {
        return c == ExitCode::kWorkgroupFault ? 3 : c == ExitCode::kDivergence ? 2 : c == ExitCode::kBackendFault ? 1 : 0;
      };
      if (rank(r.verdict) > rank(verdict)) verdict = r.verdict;
    }
  }
  // A simulated subgroup layout other than lavapipe's: what a kernel that fails under it assumes.
  std::string layout_error;
  const std::optional<sim::SubgroupLayoutChoice> layout =
      args.subgroup_layout.empty() ? std::nullopt : sim::ParseSubgroupLayout(args.subgroup_layout, layout_error);
  if (verdict != ExitCode::kOk && layout && layout->layout != sim::SubgroupLayout::kLinear) {
    const bool partial = layout->layout == sim::SubgroupLayout::kPartial;
    const char* assumption = partial ? "full subgroups (every lane active; NumSubgroups = local size / SubgroupSize)"
                                     : "linear lanes (LocalInvocationIndex = SubgroupId x SubgroupSize + SubgroupInvocationId)";
    std::fprintf(stderr, "  subgroup layout %s: a kernel that fails only under it assumes %s, which Vulkan does not promise "
                         "(docs/simulator.md, \"Subgroup layouts\")\n", args.subgroup_layout.c_str(), assumption);
    j["layout_assumption"] = {{"layout", args.subgroup_layout}, {"assumes", partial ? "full subgroups" : "linear lanes"}};
  }
  AddProvenance(j);
  if (saving) saving->Keep();  // every frame ran to its verdict: the saved calls are complete
  return {verdict, std::move(j)};
}

ExitCode RunDiff(const DiffArgs& args) {
  if (!args.junit.empty() && args.junit == args.report) ThrowInput("--junit '{}': the same file as --report", args.junit);
  std::optional<OutputFile> report, junit;
  DiffResult r = DiffToReport(args, [&](const Scene& scene) {
    report.emplace(OpenOutput(args.report, "the report", &scene));
    junit.emplace(OpenOutput(args.junit, "the JUnit report", &scene));
  });
  return WriteOutputs(r.verdict, [&] {
    report->Commit(JsonText(r.report));
    junit->Commit(JUnitXml("rayspace diff", DiffJUnit(r.report)));
  });
}

namespace {

// A saved call whose inputs fail a check deep in a pass: the message names the call, the user gave
// the directory, so the directory is named too.
template <typename F>
decltype(auto) InSavedCall(const std::string& where, F&& f) {
  try {
    return f();
  } catch (const InputError& e) {
    const std::string m = e.what();
    if (m.rfind(where, 0) == 0) throw;
    ThrowInput("{}: {}", where, m);
  }
}

// DIR/comparison.json as diff --save-inputs wrote it, checked (CheckRecorded); null when there is none.
nlohmann::json ReadRecorded(const std::string& dir) {
  const std::string file = dir + "/comparison.json";
  if (std::error_code ec; !std::filesystem::exists(file, ec)) return nullptr;
  nlohmann::json recorded;
  try {
    recorded = ParseJson(ReadInputFile(file, {"recorded comparison", kMaxTextFileBytes}));
  } catch (const JsonError& e) {
    ThrowInput("{}: not valid JSON: {}", file, e.what());
  }
  CheckRecorded(recorded, file);
  return recorded;
}

// options.KEY of the recording into `field`, unless the command line gave `option`; the value must be
// of the JSON type `is` accepts and pass `ok`. Returns whether it was applied.
template <typename T, typename Is, typename Ok>
bool Reapply(const nlohmann::json& options, const char* key, const ReplayArgs& given, const char* option, T& field,
             const std::string& file, Is is, Ok ok) {
  if (!options.contains(key) || given.given.count(option)) return false;
  const nlohmann::json& v = options[key];
  if (!is(v) || !ok(v.get<T>())) ThrowInput("{}: options.{} = {} is not a value {} takes", file, key, v.dump(), option);
  const bool changed = v.get<T>() != field;
  field = v.get<T>();
  return changed;
}

// The options the diff recorded beside the call, each applied unless the command line gives it, so that
// the call runs as the diff ran it. Returns the applied ones as a command line, for the summary.
std::string ApplyRecordedOptions(const nlohmann::json& recorded, const std::string& file, ReplayArgs& args) {
  if (!recorded.is_object() || !recorded.contains("options")) return {};
  const nlohmann::json& o = recorded["options"];
  const auto uint = [](const nlohmann::json& v) { return v.is_number_unsigned(); };
  const auto uint32 = [](const nlohmann::json& v) { return v.is_number_unsigned() && v.get<std::uint64_t>() <= UINT32_MAX; };
  const auto str = [](const nlohmann::json& v) { return v.is_string(); };
  const auto boolean = [](const nlohmann::json& v) { return v.is_boolean(); };
  const auto valid = [](auto check) {
    return [check](const auto& v) {
      try {
        check(v);
        return true;
      } catch (const InputError&) {
        return false;
      }
    };
  };
  std::string applied;
  if (Reapply(o, "split_bytes", args, "--split-bytes", args.split_bytes, file, uint,
              [](std::size_t v) { return v == 0 || (v >= 4096 && v <= (std::size_t{1} << 40)); }))
    applied += fmt::format(" --split-bytes {}", args.split_bytes);
  if (Reapply(o, "max_groups", args, "--max-groups", args.max_groups, file, uint32, [](std::uint32_t v) { return v <= 65535; }))
    applied += fmt::format(" --max-groups {}", args.max_groups);
  if (Reapply(o, "local_size", args, "--local-size", args.local_size, file, uint32, [](int v) { return v >= 1 && v <= 1024; }))
    applied += fmt::format(" --local-size {}", args.local_size);
  if (Reapply(o, "inject", args, "--inject", args.inject, file, str, valid([](const std::string& v) { ParseInject(v); })))
    applied += fmt::format(" --inject '{}'", args.inject);
  if (Reapply(o, "compare", args, "--compare", args.compare, file, str,
              [](const std::string& v) { return v == "auto" || v == "bitwise" || v == "relaxed"; }))
    applied += fmt::format(" --compare {}", args.compare);
  if (Reapply(o, "schedule", args, "--schedule", args.model.schedule, file, str, valid([](const std::string& v) { ParseSchedule(v); })))
    applied += fmt::format(" --schedule {}", args.model.schedule);
  if (Reapply(o, "check_workgroups", args, "--check-workgroups", args.model.check, file, boolean, [](bool) { return true; }))
    applied += args.model.check ? " --check-workgroups" : " --no-check-workgroups";
  if (Reapply(o, "kernels", args, "--kernel", args.kernels, file,
              [](const nlohmann::json& v) { return v.is_array() && std::all_of(v.begin(), v.end(), [](const auto& e) { return e.is_string(); }); },
              [](const KernelFiles&) { return true; }))
    for (const std::string& k : args.kernels) applied += " --kernel " + k;
  args.strict_math = vk::Context::StrictMath();
  if (Reapply(o, "strict_math", args, "--strict-math", args.strict_math, file, boolean, [](bool) { return true; }) && args.strict_math)
    applied += " --strict-math";
  return applied;
}

// How this run compares with the one recorded: reproduced (the same verdict and the same differences),
// or not, and then whether a recorded divergence is gone.
struct Reproduction {
  bool recorded = false, same = true, now_equal = false;
};

Reproduction CompareWithRecorded(const verify::CallRecord& r, const nlohmann::json& recorded) {
  Reproduction rep;
  if (recorded.is_null()) return rep;
  rep.recorded = true;
  rep.same = recorded.value("equal", !r.equal) == r.equal && recorded.contains("buffers") &&
             recorded["buffers"].size() == r.buffers.size();
  for (std::size_t i = 0; rep.same && i < r.buffers.size(); ++i) {
    nlohmann::json now;
    r.buffers[i].ToJson(now);
    // The same words, whichever backend gave them: a lavapipe recording replayed on the simulator
    // reproduces when the comparison does.
    nlohmann::json then = recorded["buffers"][i];
    now["pass"] = then.value("pass", now["pass"].get<std::string>());
    for (nlohmann::json* c : {&now, &then}) {
      c->erase("actual_backend");
      if (c->contains("first_extra")) (*c)["first_extra"].erase("backend");
    }
    rep.same &= now == then;
  }
  rep.now_equal = !rep.same && !recorded.value("equal", true) && r.equal;
  return rep;
}

void PrintReplayCall(const verify::CallRecord& r) {
  if (!r.error.empty()) std::fprintf(stderr, "  the actual backend failed: %s\n", r.error.c_str());
  for (const BufferComparison& b : r.buffers) std::printf("  %s\n", b.Summary().c_str());
  if (!r.spec.empty()) std::printf("  relaxed model: %s\n", r.spec.c_str());
  if (!r.raster.empty()) std::printf("  raster: %s\n", r.raster.c_str());
  if (!r.equal && r.within_spec) std::printf("  every difference is within the spec's precision\n");
}

// The verdict: on stdout when the call is equal and the recording reproduced; on stderr otherwise.
ExitCode PrintReplayVerdict(const verify::CallRecord& r, const Reproduction& rep, const nlohmann::json& recorded,
                            const std::string& inject) {
  if (rep.recorded && rep.same) std::printf("  recorded comparison: reproduced\n");
  if (!rep.same) {
    std::fprintf(stderr, "rayspace replay: recorded comparison: NOT reproduced%s\n",
                 rep.now_equal ? ", now equal: the recorded divergence is gone" : "");
    const std::string rec_inject = recorded.value("inject", std::string());
    if (rec_inject != inject)
      std::fprintf(stderr, "  (recorded with --inject '%s', replayed with '%s')\n", rec_inject.c_str(), inject.c_str());
    return ExitCode::kNotReproduced;
  }
  if (r.equal || r.within_spec) {
    std::printf("  %s\n", r.equal ? "equal" : "within the spec's precision");
    return ExitCode::kOk;
  }
  std::fprintf(stderr, "rayspace replay: divergent\n");
  return ExitCode::kDivergence;
}

FaultFacts ReplayFacts(const verify::BufferSet& in, const verify::PassMethod& method, const Backend& gpu) {
  FaultFacts facts;
  facts.passes.insert(method.pass(in));
  facts.split = gpu.extra_dispatches(gpu) + gpu.paged_arrays(gpu) > 0;
  facts.rows = gpu.folded_launches(gpu) > 0;
  facts.scan = method.method == "reduce" && in.scalars.is_object() && in.scalars.value("reduction", 0) == 1;
  return facts;
}

// Every file of the saved call: the report may replace none of them.
std::vector<std::filesystem::path> SavedFiles(const std::string& dir) {
  std::vector<std::filesystem::path> files;
  std::error_code ec;
  for (const auto& e : std::filesystem::directory_iterator(dir, ec)) files.push_back(e.path());
  return files;
}

}  // namespace

// The recording is read before the backend exists: its options decide how the backend is made.
ExitCode RunReplay(const ReplayArgs& given) {
  ReplayArgs args = given;
  std::string method_name;
  const verify::BufferSet in = verify::BufferSet::Load(args.dir, method_name);
  const verify::PassMethod& method = InSavedCall(args.dir + "/pass.json", [&]() -> const verify::PassMethod& {
    return verify::FindPassMethod(method_name);
  });
  CheckSavedInputs(in, args.dir);
  const nlohmann::json recorded = ReadRecorded(args.dir);
  const std::string applied = ApplyRecordedOptions(recorded, args.dir + "/comparison.json", args);
  const ScopedSettings strict([&](Settings& s) { s.strict_math |= args.strict_math; });
  OutputOptions ro{"the report", true, true, SavedFiles(args.dir)};
  OutputFile report = args.report.empty() ? OutputFile() : OutputFile(args.report, ro);
  const Injection injection = ParseInject(args.inject);
  const Backend gpu = MakeActualBackend(args.backends, args.backends_given, args.device, args.local_size, injection.kernel,
                                        {args.split_bytes, args.max_groups}, args.kernels);
  const ScopedSettings model = EmulatedKernels(args.model, static_cast<std::uint32_t>(args.local_size), gpu.subgroup_size, injection);
  // --backends sim,vulkan: the same kernels on the simulated GPU are the expected side (as diff).
  std::optional<Backend> reference;
  if (args.backends == "sim,vulkan") {
    if (!args.inject.empty()) ThrowInput("--inject with --backends sim,vulkan: plant faults against the emulator (--backends emu,sim or emu,vulkan)");
    reference = MakeBackend("sim", args.device, args.local_size, {}, {args.split_bytes, args.max_groups}, args.kernels,
                            SimulatedConfig(args.backends, 0, "forward", "", "", ""));
  }
  verify::Backends expected = reference ? verify::Backends{reference->Frame(), reference->Hierarchy()}
                                        : verify::Backends{emu::EmuFramePasses(), emu::EmuHierarchyPasses()};
  verify::Backends actual{gpu.Frame(), gpu.Hierarchy()};
  std::printf("rayspace replay: %s (%s) on %s%s\n", InSavedCall(args.dir, [&] { return method.pass(in); }).c_str(),
              method_name.c_str(), gpu.device.c_str(), reference ? (", expected from " + reference->device).c_str() : "");
  if (!applied.empty()) std::printf("  as recorded:%s\n", applied.c_str());
  nlohmann::json j = {{"dir", args.dir}, {"options", RecordedOptions(args, gpu)}};
  AddProvenance(j);
  verify::CallRecord r;
  try {
    verify::BufferSet out;
    const bool relaxed = args.compare == "relaxed" || (args.compare == "auto" && !gpu.correctly_rounded);
    r = InSavedCall(args.dir, [&] { return verify::RunAndCompare(method, in, expected, actual, out, nullptr, relaxed); });
  } catch (const wg::CheckError& e) {
    j["workgroup_checker"] = PrintCheckerReports(e.result);
    return WriteOutputs(ExitCode::kWorkgroupFault, [&] { report.Commit(JsonText(j)); });
  }
  // The kernels given here, not the recording's: a recorded diff's kernels serve its other calls too.
  CheckKernelsRan(gpu, given.kernels);
  PrintReplayCall(r);
  // A simulated device's checker finding on the kernel: exit 6, as diff gives it.
  if (!r.error_checker.empty()) {
    j["simulator_checker"] = SimCheckerJson(r.error_checker, r.pass, r.error_finding);
    PrintSimChecker(j["simulator_checker"]);
    return WriteOutputs(ExitCode::kWorkgroupFault, [&] { report.Commit(JsonText(j)); });
  }
  // The device could not finish the call: nothing compared, exit 7 as diff gives it.
  if (r.error_device_fault) {
    j["backend_fault"] = {{"pass", r.pass}, {"error", r.error}};
    std::fprintf(stderr, "rayspace replay: the actual backend failed at pass %s; nothing was compared: %s\n", r.pass.c_str(),
                 r.error.c_str());
    return WriteOutputs(ExitCode::kBackendFault, [&] { report.Commit(JsonText(j)); });
  }
  // A fault given here that cannot fire leaves no verdict; the recording's own fault may belong to
  // another call of its frame, which is worth a note only.
  if (const std::string why = FaultCannotFire(args.inject, injection, ReplayFacts(in, method, gpu)); !why.empty()) {
    if (!given.inject.empty()) ThrowInput("{}", why);
    std::fprintf(stderr, "rayspace replay: note: %s (the recorded --inject)\n", why.c_str());
  }
  const Reproduction rep = CompareWithRecorded(r, recorded);
  const ExitCode verdict = PrintReplayVerdict(r, rep, recorded, args.inject);
  j.update(CallJson(r));
  j["recorded"] = rep.recorded ? nlohmann::json{{"reproduced", rep.same}, {"now_equal", rep.now_equal}} : nlohmann::json(nullptr);
  return WriteOutputs(verdict, [&] { report.Commit(JsonText(j)); });
}

}  // namespace rayspace::app
