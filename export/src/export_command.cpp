#include "rayspace/export/export_command.h"

#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <set>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "rayspace/frame/backend_setup.h"
#include "rayspace/diff/diff_command.h"
#include "rayspace/export/export_recording.h"
#include "rayspace/export/export_writer.h"
#include "rayspace/frame/kernel_model.h"
#include "rayspace/error.h"
#include "rayspace/input_file.h"
#include "rayspace/gpu/passes.h"
#include "rayspace/json_text.h"
#include "rayspace/output_file.h"
#include "rayspace/pass_registry.h"
#include "rayspace/verify/call_codec.h"
#include "rayspace/verify/pass_table.h"

namespace rayspace::app {
namespace {

namespace fs = std::filesystem;

// The saved call's directory: it must hold pass.json (a directory of saved calls is named as such).
void CheckSavedDir(const std::string& dir) {
  std::error_code ec;
  if (!fs::exists(dir, ec)) ThrowInput("{}: no such directory", dir);
  if (!fs::is_directory(dir, ec)) ThrowInput("{}: not a directory (expected a call saved by diff --save-inputs)", dir);
  if (fs::is_regular_file(fs::path(dir) / "pass.json", ec)) return;
  fs::path first;  // the first saved call inside, by name
  for (const fs::directory_entry& e : fs::directory_iterator(dir, ec))
    if (fs::is_regular_file(e.path() / "pass.json", ec) && (first.empty() || e.path() < first)) first = e.path();
  if (!first.empty()) ThrowInput("{}: a directory of saved calls, not one call; name one of them, e.g. {}", dir, first.string());
  ThrowInput("{}: not a call saved by diff --save-inputs (no pass.json)", dir);
}

// --out: a new directory or an empty one, so that an export never mixes with other files.
void CheckOutDir(const std::string& out) {
  std::error_code ec;
  if (!fs::exists(out, ec)) {
    CheckOutputParent(out, "--out");
    return;
  }
  if (!fs::is_directory(out, ec)) ThrowInput("--out {}: exists and is not a directory", out);
  if (!fs::is_empty(out, ec)) ThrowInput("--out {}: not empty; the export writes into a new or empty directory", out);
}

// What comparison.json recorded about the run that saved the call (each key optional).
struct Recorded {
  std::string inject;
  std::vector<std::string> kernels;  // --kernel PASS=FILE of the recorded diff
  std::uint32_t local_size = 0, max_groups = 0;
  std::size_t split_bytes = 0;
};

std::uint64_t RecordedCount(const nlohmann::json& j, const char* key, const std::string& file) {
  if (!j.contains(key) || j[key].is_null()) return 0;
  if (!j[key].is_number_unsigned()) ThrowInput("{}: 'options.{}' must be a non-negative integer", file, key);
  return j[key].get<std::uint64_t>();
}

// The options diff --save-inputs recorded under "options" (each key optional).
Recorded ReadRecordedOptions(const std::string& dir) {
  const std::string file = (fs::path(dir) / "comparison.json").string();
  Recorded r;
  if (std::error_code ec; !fs::exists(file, ec)) return r;
  nlohmann::json j;
  try {
    j = ParseJson(ReadInputFile(file, {"recorded comparison", kMaxTextFileBytes}));
  } catch (const JsonError& e) {
    ThrowInput("{}: not valid JSON: {}", file, e.what());
  }
  if (!j.is_object()) ThrowInput("{}: expected a JSON object", file);
  if (!j.contains("options")) return r;
  if (!j["options"].is_object()) ThrowInput("{}: 'options' must be an object", file);
  j = j["options"];
  if (j.contains("inject") && !j["inject"].is_string() && !j["inject"].is_null())
    ThrowInput("{}: 'options.inject' must be a string", file);
  if (j.contains("inject") && j["inject"].is_string()) r.inject = j["inject"].get<std::string>();
  if (j.contains("kernels") && !j["kernels"].is_null()) {
    if (!j["kernels"].is_array()) ThrowInput("{}: 'options.kernels' must be an array of PASS=FILE strings", file);
    for (const nlohmann::json& k : j["kernels"]) {
      if (!k.is_string()) ThrowInput("{}: 'options.kernels' must be an array of PASS=FILE strings", file);
      r.kernels.push_back(k.get<std::string>());
    }
  }
  r.local_size = static_cast<std::uint32_t>(std::min<std::uint64_t>(RecordedCount(j, "local_size", file), 1u << 20));
  r.split_bytes = RecordedCount(j, "split_bytes", file);
  r.max_groups = static_cast<std::uint32_t>(std::min<std::uint64_t>(RecordedCount(j, "max_groups", file), 65535));
  return r;
}

// Where `bytes` at `dst` lie among the call's outputs right now (a read-back lands there).
template <typename C, typename R>
std::optional<Landing> Land(const C& call, const R* result, const void* dst, std::size_t bytes) {
  std::optional<Landing> found;
  const auto at = reinterpret_cast<std::uintptr_t>(dst);
  verify::ForEachOutputRange(call, result, [&](std::string_view name, const void* first, std::size_t size, std::size_t elem) {
    const auto f = reinterpret_cast<std::uintptr_t>(first);
    if (!found && bytes && at >= f && at - f + bytes <= size) found = Landing{std::string(name), at - f, elem};
  });
  return found;
}

// Runs one call on the Vulkan backend with `rec` recording it; returns its outputs.
template <typename C>
verify::BufferSet Capture(const verify::BufferSet& in, gpu_backend::VulkanPasses& gpu, Recording& rec) {
  verify::DecodedCall<C> d = verify::DecodeCall<C>(in);
  emu::CheckInputs(d.call);
  gpu_backend::VulkanOut<C> out;
  rec.Start([&](const void* dst, std::size_t bytes) { return Land(d.call, &out, dst, bytes); });
  const vk::Status s = gpu.Run(d.call, out);
  rec.Stop();
  if (!s) throw std::runtime_error(fmt::format("Vulkan backend, pass {}: {}", C::kName, s.message));
  if constexpr (std::is_void_v<typename C::Result>) return verify::EncodeOutputs(d.call, nullptr);
  else return verify::EncodeOutputs(d.call, &out);
}

using CaptureFn = verify::BufferSet (*)(const verify::BufferSet&, gpu_backend::VulkanPasses&, Recording&);

CaptureFn FindCapture(const std::string& method) {
  static const std::map<std::string, CaptureFn> kCaptures = [] {
    std::map<std::string, CaptureFn> m;
#define RS_CAPTURE(C) m[std::string(emu::call::C::kName)] = &Capture<emu::call::C>;
    RS_FRAME_CALLS(RS_CAPTURE)
    RS_HIERARCHY_CALLS(RS_CAPTURE)
#undef RS_CAPTURE
    return m;
  }();
  return kCaptures.at(method);  // FindPassMethod has checked the name
}

// The built-in kernels (no fault: the sequence is the one a correct device takes) on the chosen
// device, every kernel made with `rec` watching.
std::unique_ptr<gpu_backend::VulkanPasses> MakeRecordedPasses(int device, const ExportInfo& info, Recording& rec) {
  std::unique_ptr<gpu_backend::VulkanPasses> gpu;
  const vk::Status s = [&] {
    const ScopedSettings observed([&](Settings& settings) { settings.observer = &rec; });
    return gpu_backend::VulkanPasses::Create(device, {}, gpu, info.local_size);
  }();
  if (!s && s.message.rfind("--", 0) == 0) ThrowInput("{}", s.message);
  if (!s) throw std::runtime_error("Vulkan: " + s.message);
  gpu->LimitForTesting(info.split_bytes, info.max_groups);
  return gpu;
}

// The recorded outputs must be the emulator's: then the sequence (its sizes, counts and carries,
// which the host computes from what it reads back) is the one a correct device takes.
void CheckAgainstEmulator(const verify::PassMethod& method, const verify::BufferSet& in, const verify::BufferSet& actual,
                          const ExportInfo& info) {
  verify::Backends emulator{emu::EmuFramePasses(), emu::EmuHierarchyPasses()};
  const verify::BufferSet expected = method.run(in, emulator);
  for (const auto& [name, blob] : expected.blobs()) {
    auto it = actual.blobs().find(name);
    const BufferComparison c = verify::CompareBlobs(info.pass, name, blob, it == actual.blobs().end() ? verify::Blob{} : it->second, "vulkan");
    if (!c.Equal())
      ThrowInput("{}: pass {}: the built-in kernels on '{}' do not give the emulator's bits ({}); record on a device that "
                 "does (--device N, see rayspace devices) or with --strict-math",
                 info.saved, info.pass, info.device, c.Summary());
  }
}

// A --kernel for a pass whose kernel this call never dispatches would be exported nowhere: refused,
// as a run that never launches a user's kernel is (backend_setup.h, CheckKernelsRan).
void CheckOwnKernelsUsed(const Recording& rec, const ExportInfo& info) {
  std::set<std::string> dispatched;
  for (const RecordedStep& s : rec.steps())
    if (s.kind == StepKind::kDispatch) dispatched.insert(rec.pipelines()[s.id].pass);
  for (const std::string& k : info.kernel_files) {
    const std::string pass = k.substr(0, k.find('='));
    if (!dispatched.count(pass))
      ThrowInput("--kernel '{}': {} (pass {}) dispatches no {} kernel, so it would be exported nowhere; export a call of pass {}",
                 k, info.label, info.pass, pass, pass);
  }
}

// Writes into a fresh sibling directory and renames it to `out` when complete, so that a failed or
// interrupted export (SIGTERM included: TempDirectory) leaves nothing behind.
ExportCounts WriteAtomically(const std::string& out, const Recording& rec, const ExportInfo& info) {
  fs::path tmp = fs::path(out).lexically_normal();
  if (tmp.filename().empty()) tmp = tmp.parent_path();
  tmp += fmt::format(".partial-{}", static_cast<long>(::getpid()));
  TempDirectory partial(tmp);
  const ExportCounts counts = WriteExport(tmp, rec, info);
  std::error_code ec;
  if (fs::exists(out)) fs::remove(out);
  fs::rename(tmp, out, ec);
  if (ec) ThrowInput("--out {}: cannot rename {} to it: {}", out, tmp.string(), ec.message());
  partial.Keep();
  return counts;
}

ExportInfo Describe(const ExportArgs& args, const verify::PassMethod& method, const verify::BufferSet& in) {
  const Recorded recorded = ReadRecordedOptions(args.dir);
  ExportInfo info;
  info.saved = args.dir;
  info.label = fs::path(args.dir).lexically_normal().filename().string();
  if (info.label.empty()) info.label = fs::path(args.dir).lexically_normal().parent_path().filename().string();
  info.pass = method.pass(in);
  info.method = method.method;
  info.inject = args.inject_given ? args.inject : recorded.inject;
  info.faults = ParseInject(info.inject).kernel;  // a fault planted in the emulator changes no kernel
  info.kernel_files = args.kernels_given ? args.kernels : recorded.kernels;
  KernelFiles files;
  files.assign(info.kernel_files.begin(), info.kernel_files.end());
  info.kernels = LoadKernelFiles(files);
  info.local_size = static_cast<std::uint32_t>(args.local_size ? args.local_size : recorded.local_size ? recorded.local_size : 64);
  info.split_bytes = args.split_bytes ? args.split_bytes : recorded.split_bytes;
  info.max_groups = args.max_groups ? args.max_groups : recorded.max_groups;
  info.strict_math = vk::Context::StrictMath();
  return info;
}

void PrintSummary(const ExportArgs& args, const ExportInfo& info, const ExportCounts& c) {
  std::printf("rayspace export: %s (pass %s, method %s), recorded on %s\n", info.label.c_str(), info.pass.c_str(),
              info.method.c_str(), info.device.c_str());
  std::printf("  %zu dispatch(es) in %zu submit(s), %zu buffer(s), %zu upload(s), %zu read-back(s) (%zu of them outputs); "
              "outputs equal to the emulator's\n",
              c.dispatches, c.submits, c.buffers, c.writes, c.reads, c.output_reads);
  std::printf("  kernels: %s\n", c.kernels.c_str());
  if (!info.inject.empty() && !c.fault_set)
    std::printf("  planted fault %s: not in this call's kernels; they are the built-in ones\n", info.inject.c_str());
  std::printf("  wrote %s: repro.c, README.md, sequence.txt, call.json, %zu kernel(s), %zu input(s), %zu expected read-back(s)\n",
              args.out.c_str(), c.pipelines, c.writes, c.reads);
  std::printf("  build and run: cd %s && cc repro.c -lvulkan -o repro && ./repro\n", args.out.c_str());
}

}  // namespace

ExitCode RunExport(const ExportArgs& args) {
  CheckSavedDir(args.dir);
  CheckOutDir(args.out);
  std::string method_name;
  const verify::BufferSet in = verify::BufferSet::Load(args.dir, method_name);
  const verify::PassMethod& method = verify::FindPassMethod(method_name);
  CheckSavedInputs(in, args.dir);
  ExportInfo info = Describe(args, method, in);
  const std::optional<PassId> id = FindPass(info.pass);
  if (id && Pass(*id).graphics)
    ThrowInput("{}: pass {} cannot be exported: it draws with a graphics pipeline (render pass, colour and depth "
               "attachments), and the reproducer replays compute dispatches only",
               args.dir, info.pass);
  Recording rec;
  std::unique_ptr<gpu_backend::VulkanPasses> gpu = MakeRecordedPasses(args.device, info, rec);
  info.device = gpu->context().device_name();
  info.driver = gpu->context().driver();
  const verify::BufferSet actual = FindCapture(method_name)(in, *gpu, rec);
  if (!rec.problem().empty()) ThrowInput("{}: pass {} cannot be exported: {}", args.dir, info.pass, rec.problem());
  CheckOwnKernelsUsed(rec, info);
  CheckAgainstEmulator(method, in, actual, info);
  const ExportCounts counts = WriteAtomically(args.out, rec, info);
  PrintSummary(args, info, counts);
  return ExitCode::kOk;
}

}  // namespace rayspace::app
