#include "rayspace/export/export_writer.h"

#include <fstream>
#include <set>
#include <sstream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "rayspace/error.h"
#include "rayspace/gpu/kernel_check.h"
#include "rayspace/output_file.h"
#include "repro_source.h"

namespace rayspace::app {
namespace {

namespace fs = std::filesystem;

void WriteFile(const fs::path& path, const void* data, std::size_t bytes) {
  std::ofstream f(path, std::ios::binary);
  f.write(static_cast<const char*>(data), static_cast<std::streamsize>(bytes));
  f.close();
  if (!f) ThrowInput("{}: cannot write", path.string());
  TestSignalPoint("export.file");
}

void WriteText(const fs::path& path, const std::string& text) { WriteFile(path, text.data(), text.size()); }

// The block names of a kernel's bindings (empty where the SPIR-V carries none).
std::map<std::uint32_t, std::string> BlockNames(const RecordedPipeline& p) {
  std::map<std::uint32_t, std::string> names;
  gpu_backend::KernelInterface ki;
  if (gpu_backend::ReflectKernel(p.spirv, ki))
    for (const gpu_backend::KernelInterface::Binding& b : ki.bindings) names[b.binding] = b.name;
  return names;
}

// Each buffer by where a dispatch first binds it ("trim/1/Sums": binding 1 of trim's kernel, the block
// Sums), so that a mismatch names something a kernel developer finds in the kernel's source.
std::map<std::uint32_t, std::string> BufferLabels(const Recording& rec) {
  std::map<std::uint32_t, std::map<std::uint32_t, std::string>> blocks;  // by pipeline
  std::map<std::uint32_t, std::string> labels;
  for (const RecordedStep& s : rec.steps()) {
    if (s.kind != StepKind::kDispatch) continue;
    auto it = blocks.find(s.id);
    if (it == blocks.end()) it = blocks.emplace(s.id, BlockNames(rec.pipelines()[s.id])).first;
    for (std::uint32_t i = 0; i < s.buffers.size(); ++i) {
      const std::string& block = it->second[i];
      labels.try_emplace(s.buffers[i], fmt::format("{}/{}{}{}", rec.pipelines()[s.id].pass, i, block.empty() ? "" : "/", block));
    }
  }
  return labels;
}

// The recorded pipelines a dispatch uses, numbered in order of first use.
std::map<std::uint32_t, std::uint32_t> UsedPipelines(const Recording& rec) {
  std::map<std::uint32_t, std::uint32_t> used;
  for (const RecordedStep& s : rec.steps())
    if (s.kind == StepKind::kDispatch) used.try_emplace(s.id, static_cast<std::uint32_t>(used.size()));
  return used;
}

std::string PushWords(const std::vector<std::uint8_t>& push) {
  std::string out;
  for (std::size_t i = 0; i < push.size(); i += 4) {
    std::uint32_t w = 0;
    for (std::size_t k = 0; k < 4 && i + k < push.size(); ++k) w |= std::uint32_t{push[i + k]} << (8 * k);
    out += fmt::format(" {:08x}", w);
  }
  return out;
}

// The pipelines, with the planted fault of their pass in specialization constant 0, and their SPIR-V.
std::string PipelineLines(const fs::path& dir, const Recording& rec, const ExportInfo& info, ExportCounts& counts) {
  std::map<std::uint32_t, std::uint32_t> used = UsedPipelines(rec);
  std::vector<std::uint32_t> order(used.size());
  for (const auto& [recorded, id] : used) order[id] = recorded;
  std::string lines;
  for (std::uint32_t id = 0; id < order.size(); ++id) {
    const RecordedPipeline& p = rec.pipelines()[order[id]];
    auto fault = info.faults.find(p.pass);
    const std::uint32_t planted = fault == info.faults.end() ? p.spec[0] : fault->second;
    counts.fault_set |= planted != 0;
    const std::string file = fmt::format("kernels/{}.spv", p.pass);
    // A user's kernel replaces the built-in one the sequence was recorded with: same contract, same
    // dispatches, and the expected read-backs are the emulator's, so the reproducer shows where it differs.
    const auto own = info.kernels.find(p.pass);
    const std::vector<std::uint32_t>& spirv = own == info.kernels.end() ? p.spirv : own->second;
    WriteFile(dir / file, spirv.data(), spirv.size() * 4);
    lines += fmt::format("pipeline {} {} {} {} {} {} {}\n", id, p.pass, file, p.bindings, planted, p.spec[1], p.spec[2]);
    std::string note = planted ? fmt::format(" (planted fault {})", planted) : "";
    if (own != info.kernels.end()) {
      for (const std::string& k : info.kernel_files)
        if (k.rfind(p.pass + "=", 0) == 0) note += fmt::format(" (your kernel {})", k.substr(p.pass.size() + 1));
      ++counts.own_kernels;
    }
    counts.kernels += fmt::format("{}{}{}", counts.kernels.empty() ? "" : ", ", p.pass, note);
  }
  counts.pipelines = order.size();
  return lines;
}

// One line per recorded step; writes each upload and each expected read-back to its own file.
std::string StepLines(const fs::path& dir, const Recording& rec, ExportCounts& counts) {
  const std::map<std::uint32_t, std::string> labels = BufferLabels(rec);
  const std::map<std::uint32_t, std::uint32_t> pipes = UsedPipelines(rec);
  std::string lines;
  for (const RecordedStep& s : rec.steps()) {
    switch (s.kind) {
      case StepKind::kBuffer: {
        auto it = labels.find(s.id);
        lines += fmt::format("buffer {} {} {}\n", s.id, s.bytes, it == labels.end() ? "unbound" : it->second);
        ++counts.buffers;
        break;
      }
      case StepKind::kWrite: {
        const std::string file = fmt::format("inputs/w{:04d}.bin", counts.writes++);
        WriteFile(dir / file, s.data.data(), s.data.size());
        lines += fmt::format("write {} {} {}\n", s.id, file, s.bytes);
        break;
      }
      case StepKind::kZero: lines += fmt::format("zero {}\n", s.id); break;
      case StepKind::kDispatch: {
        lines += fmt::format("dispatch {} {} {} {}{}", pipes.at(s.id), s.gx, s.gy, s.data.size(), PushWords(s.data));
        for (std::uint32_t b : s.buffers) lines += fmt::format(" {}", b);
        lines += "\n";
        ++counts.dispatches;
        break;
      }
      case StepKind::kSubmit: lines += "submit\n"; ++counts.submits; break;
      case StepKind::kRead: {
        const std::string file = fmt::format("expected/r{:04d}.bin", counts.reads++);
        WriteFile(dir / file, s.data.data(), s.data.size());
        const bool lands = !s.landing.output.empty();
        counts.output_reads += lands;
        lines += fmt::format("read {} {} {} {} {} {}\n", s.id, s.bytes, file, lands ? s.landing.output : "-", s.landing.offset,
                             s.landing.element_bytes);
        break;
      }
      case StepKind::kFree: lines += fmt::format("free {}\n", s.id); break;
    }
  }
  return lines;
}

std::string Options(const ExportInfo& info) {
  std::string o = fmt::format("local size {}", info.local_size);
  if (info.strict_math) o += ", --strict-math";
  if (info.split_bytes) o += fmt::format(", --split-bytes {}", info.split_bytes);
  if (info.max_groups) o += fmt::format(", --max-groups {}", info.max_groups);
  return o;
}

// The README: fixed text around the call's facts.
std::string Readme(const ExportInfo& info, const ExportCounts& c) {
  const std::string fault = info.inject.empty() ? std::string("none")
                            : c.fault_set     ? fmt::format("`{}`, set as specialization constant 0 of its pipeline", info.inject)
                            : info.faults.empty()
                                ? fmt::format("`{}` is planted in the emulator, not in a kernel: none here", info.inject)
                                : fmt::format("`{}` is in another pass's kernel: none here", info.inject);
  return fmt::format(R"(# Reproducer: {label}

One pass call of a rayspace frame (pass `{pass}`, method `{method}`), saved by `rayspace diff
--save-inputs` and exported by `rayspace export`. It runs with nothing but the Vulkan loader.

- Kernels: {kernels}.
- Planted fault: {fault}.
- {dispatches} dispatch(es) in {submits} submit(s) over {buffers} storage buffer(s), {writes} upload(s)
  and {reads} read-back(s). {output_reads} of the read-backs land in the pass's outputs as read; the
  others are intermediate: results the host merges or converts into the outputs (occlusion flags
  or'ed into the caller's, 32-bit flags narrowed to bytes), or counts and block sums that size what it
  does next.
- Expected: the bits the rayspace emulator computes for this call. The dispatch sequence was recorded
  with the built-in kernels on {device} ({driver}; {options}), whose outputs were first checked equal
  to the emulator's bit for bit.{own}

## Build and run

```sh
cc repro.c -lvulkan -o repro
./repro                  # in this directory; or ./repro DIR
./repro --device 1       # the second device the loader lists (default: the first with compute and Vulkan 1.2)
./repro --validate       # also REPRO_VALIDATE=1: VK_LAYER_KHRONOS_validation with synchronization validation
```

It prints `equal` or the first mismatch: the read-back, its buffer (named by the kernel and binding
that first bind it and the binding's block name), the pass output, element and word it lands in,
and the expected and actual words in hexadecimal and as floats. Exit codes: 0 every read-back equal,
1 a read-back differs, 2 bad arguments or files, 3 no usable device or a failed Vulkan call, 4 the
validation layer reported a message.

The device needs Vulkan 1.2, and for some kernels `shaderInt64`, `shaderBufferInt64Atomics`,
`shaderFloat64` (the grid build), subgroup arithmetic, ballot and shuffle in compute, and
`shaderSignedZeroInfNanPreserveFloat32` (and `Float64` for the grid build; the kernels declare
SignedZeroInfNanPreserve). On devices whose division and square root are not correctly
rounded, export with `rayspace --strict-math export ...` for bits that hold on any conformant device.

## Files

- `repro.c`: the program; its first comment describes `sequence.txt`.
- `sequence.txt`: the steps in order: `pipeline` (SPIR-V, bindings, specialization constants: planted
  fault, local size, strict math), `buffer` (size, zeroed), `write` and `zero` (host uploads),
  `dispatch` (pipeline, workgroups x and y, push-constant bytes and words, one buffer per binding;
  each followed by a barrier from compute writes to compute, transfer and host accesses), `submit`,
  `read` (bytes from the buffer's start, compared with an expected file) and `free`.
- `kernels/*.spv`: one compute kernel per pipeline (entry point `main`).
- `inputs/w*.bin`: what the host writes, raw little-endian, in the std430 layout of rayspace's
  `core/contract/include/rayspace/layout.h`.
- `expected/r*.bin`: what each read-back must give.
- `call.json`: the same facts for tools.
)",
                     fmt::arg("label", info.label), fmt::arg("pass", info.pass), fmt::arg("method", info.method),
                     fmt::arg("kernels", c.kernels), fmt::arg("fault", fault), fmt::arg("dispatches", c.dispatches),
                     fmt::arg("submits", c.submits), fmt::arg("buffers", c.buffers), fmt::arg("writes", c.writes),
                     fmt::arg("reads", c.reads), fmt::arg("output_reads", c.output_reads), fmt::arg("device", info.device),
                     fmt::arg("driver", info.driver), fmt::arg("options", Options(info)),
                     fmt::arg("own", info.kernels.empty() ? std::string()
                                                          : "\n- Your kernels (`--kernel`) are exported in place of the built-in ones the sequence "
                                                            "was\n  recorded with: a read-back that differs is where yours departs from the emulator."));
}

nlohmann::json CallJson(const ExportInfo& info, const ExportCounts& c) {
  nlohmann::json faults = nlohmann::json::object();
  for (const auto& [pass, fault] : info.faults) faults[pass] = fault;
  return {{"call", info.label},     {"saved", info.saved},          {"pass", info.pass},
          {"method", info.method},  {"inject", info.inject},        {"kernel_faults", faults},
          {"device", info.device},  {"driver", info.driver},        {"local_size", info.local_size},
          {"strict_math", info.strict_math}, {"split_bytes", info.split_bytes}, {"max_groups", info.max_groups},
          {"pipelines", c.pipelines}, {"buffers", c.buffers},       {"writes", c.writes},
          {"dispatches", c.dispatches}, {"submits", c.submits},     {"reads", c.reads},
          {"output_reads", c.output_reads}, {"kernel_files", info.kernel_files}};
}

}  // namespace

ExportCounts WriteExport(const fs::path& dir, const Recording& rec, const ExportInfo& info) {
  for (const char* sub : {"kernels", "inputs", "expected"}) fs::create_directory(dir / sub);
  ExportCounts counts;
  std::string sequence = fmt::format("rayspace-repro 1\n# {}: pass {} (method {}), recorded on {}; {}\n", info.label,
                                     info.pass, info.method, info.device, Options(info));
  sequence += PipelineLines(dir, rec, info, counts);
  sequence += StepLines(dir, rec, counts);
  WriteText(dir / "sequence.txt", sequence);
  WriteText(dir / "repro.c", std::string(kReproSource));
  WriteText(dir / "README.md", Readme(info, counts));
  WriteText(dir / "call.json", CallJson(info, counts).dump(2) + "\n");
  return counts;
}

}  // namespace rayspace::app
