#include "rayspace/sim/export_run.h"

#include <algorithm>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <sstream>

#include <fmt/format.h>

#include "rayspace/error.h"
#include "rayspace/sim/program.h"

namespace rayspace::sim {
namespace {

namespace fs = std::filesystem;

constexpr std::uint64_t kMaxBufferBytes = std::uint64_t{1} << 30;

double Seconds(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

KernelTiming& TimingOf(ExportRun& run, const std::string& kernel) {
  for (KernelTiming& k : run.kernels)
    if (k.kernel == kernel) return k;
  run.kernels.push_back({kernel});
  return run.kernels.back();
}

std::vector<std::uint8_t> ReadBytes(const fs::path& path, const std::string& where) {
  std::ifstream in(path, std::ios::binary);
  if (!in) ThrowInput("{}: cannot read {}", where, path.string());
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

std::uint64_t Number(const std::string& word, const std::string& where, int base = 10) {
  std::size_t used = 0;
  std::uint64_t v = 0;
  try {
    v = std::stoull(word, &used, base);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used == 0 || used != word.size()) ThrowInput("{}: '{}' is not a number", where, word);
  return v;
}

}  // namespace

bool ExportRun::Equal() const {
  return std::all_of(reads.begin(), reads.end(), [](const ReadBackResult& r) { return r.equal; });
}

// Long: one branch per step of sequence.txt, read in one pass as repro.c replays it.
ExportRun RunExport(const std::string& dir, const DeviceConfig& device) {
  const fs::path root(dir);
  const fs::path seq_path = root / "sequence.txt";
  std::ifstream seq(seq_path);
  if (!seq) ThrowInput("{}: not an export directory (no sequence.txt)", dir);
  ExportRun run;
  std::map<std::uint64_t, std::vector<std::uint8_t>> buffers;
  std::map<std::uint64_t, std::string> labels;
  std::map<std::uint64_t, Program> pipelines;
  std::string line;
  int number = 0;
  while (std::getline(seq, line)) {
    ++number;
    const std::string where = fmt::format("{} line {}", seq_path.string(), number);
    if (number == 1) {
      if (line != "rayspace-repro 1") ThrowInput("{}: expected 'rayspace-repro 1'", where);
      continue;
    }
    if (line.empty()) continue;
    if (line[0] == '#') {
      if (run.call.empty()) run.call = line.substr(2, line.find(':') == std::string::npos ? std::string::npos : line.find(':') - 2);
      continue;
    }
    std::istringstream words(line);
    std::vector<std::string> w{std::istream_iterator<std::string>(words), std::istream_iterator<std::string>()};
    const auto need = [&](std::size_t n) {
      if (w.size() < n) ThrowInput("{}: '{}' needs {} fields", where, w[0], n);
    };
    const auto buffer = [&](const std::string& id) -> std::vector<std::uint8_t>& {
      const auto it = buffers.find(Number(id, where));
      if (it == buffers.end()) ThrowInput("{}: no buffer {}", where, id);
      return it->second;
    };
    const std::string& step = w[0];
    if (step == "pipeline") {
      need(8);
      const std::vector<std::uint8_t> bytes = ReadBytes(root / w[3], where);
      if (bytes.size() % 4 != 0) ThrowInput("{}: {} is not SPIR-V words", where, w[3]);
      std::vector<std::uint32_t> spirv(bytes.size() / 4);
      std::memcpy(spirv.data(), bytes.data(), bytes.size());
      const Specialization spec = {{0, std::to_string(Number(w[5], where))}, {1, std::to_string(Number(w[6], where))},
                                   {2, std::to_string(Number(w[7], where))}};
      const auto t0 = std::chrono::steady_clock::now();
      pipelines[Number(w[1], where)] = Prepare(spirv, spec, w[2]);
      TimingOf(run, w[2]).prepare_s += Seconds(t0);
    } else if (step == "buffer") {
      need(3);
      // A storage buffer is bound whole: at most a binding's range (lavapipe's is 128 MiB).
      const std::uint64_t bytes = Number(w[2], where);
      if (bytes > kMaxBufferBytes) ThrowInput("{}: a buffer of {} bytes, beyond the {} one binding may hold", where, bytes, kMaxBufferBytes);
      buffers[Number(w[1], where)].assign(bytes, 0);
      labels[Number(w[1], where)] = w.size() > 3 ? w[3] : w[1];
    } else if (step == "write") {
      need(4);
      std::vector<std::uint8_t>& b = buffer(w[1]);
      const std::vector<std::uint8_t> data = ReadBytes(root / w[2], where);
      const std::uint64_t n = Number(w[3], where);
      if (data.size() != n || n > b.size()) ThrowInput("{}: {} holds {} bytes, for a write of {} into {}", where, w[2], data.size(), n, b.size());
      std::copy(data.begin(), data.end(), b.begin());
    } else if (step == "zero") {
      need(2);
      std::vector<std::uint8_t>& b = buffer(w[1]);
      std::fill(b.begin(), b.end(), 0);
    } else if (step == "dispatch") {
      need(5);
      const auto it = pipelines.find(Number(w[1], where));
      if (it == pipelines.end()) ThrowInput("{}: no pipeline {}", where, w[1]);
      Dispatch d;
      d.groups[0] = static_cast<std::uint32_t>(Number(w[2], where));
      d.groups[1] = static_cast<std::uint32_t>(Number(w[3], where));
      d.subgroup_size = device.subgroup_size;
      d.schedule = device.schedule;
      d.step_limit = device.step_limit;
      d.checks = device.checks;
      d.arithmetic = device.arithmetic;
      d.layout = device.layout;
      d.dispatch_index = run.dispatches;
      const std::uint64_t push_bytes = Number(w[4], where);
      const std::size_t push_words = (push_bytes + 3) / 4;
      need(5 + push_words);
      std::vector<std::uint8_t> push(push_words * 4);
      for (std::size_t k = 0; k < push_words; ++k) {
        const auto v = static_cast<std::uint32_t>(Number(w[5 + k], where, 16));
        std::memcpy(push.data() + 4 * k, &v, 4);
      }
      push.resize(push_bytes);
      d.push = push;
      for (std::size_t k = 5 + push_words; k < w.size(); ++k) {
        std::vector<std::uint8_t>& b = buffer(w[k]);
        d.bindings.push_back({b.data(), b.size()});
      }
      for (const Variable& v : it->second.variables)
        if (v.binding != ~0u && v.binding >= d.bindings.size())
          ThrowInput("{}: kernel {} reads binding {}, and the dispatch binds {} buffers", where, it->second.name, v.binding, d.bindings.size());
      const auto t0 = std::chrono::steady_clock::now();
      const std::uint64_t before = run.stats.lane_instructions;
      Run(it->second, d, run.stats);
      KernelTiming& k = TimingOf(run, it->second.name);
      k.run_s += Seconds(t0);
      k.lane_instructions += run.stats.lane_instructions - before;
      ++k.dispatches;
      ++run.dispatches;
    } else if (step == "read") {
      need(3);
      const std::vector<std::uint8_t>& b = buffer(w[1]);
      const std::uint64_t n = Number(w[2], where);
      const std::vector<std::uint8_t> expected = ReadBytes(root / w[3], where);
      if (expected.size() != n || n > b.size()) ThrowInput("{}: {} holds {} bytes, for a read of {}", where, w[3], expected.size(), n);
      ReadBackResult r{w[3], labels[Number(w[1], where)], true, {}};
      for (std::size_t i = 0; i + 4 <= n; i += 4)
        if (std::memcmp(expected.data() + i, b.data() + i, 4) != 0) {
          std::uint32_t e = 0, a = 0;
          std::memcpy(&e, expected.data() + i, 4);
          std::memcpy(&a, b.data() + i, 4);
          r.equal = false;
          r.mismatch = fmt::format("word {}: expected 0x{:08x} got 0x{:08x}", i / 4, e, a);
          break;
        }
      run.reads.push_back(std::move(r));
    } else if (step == "free") {
      need(2);
      buffers.erase(Number(w[1], where));
    } else if (step != "submit") {
      ThrowInput("{}: unknown step '{}'", where, step);
    }
  }
  return run;
}

}  // namespace rayspace::sim
