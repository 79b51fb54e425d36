// Bytes as a SPIR-V module for the simulated GPU: the loader (spirv-val, the scope check, spirv-opt's
// preparation, decoding) and, when it accepts the module, one small dispatch of it with every
// checker on. Every outcome must be a prepared module and a run, a one-line InputError (a module
// refused) or a one-line SimError (a fault of the kernel); anything else aborts.
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "rayspace/error.h"
#include "rayspace/sim/executor.h"
#include "rayspace/sim/program.h"

namespace {

void RequireOneLine(const char* what, const char* kind) {
  const std::string msg = what;
  if (msg.empty() || msg.find('\n') != std::string::npos) {
    std::fprintf(stderr, "error message: '%s'\n", msg.c_str());
    std::fprintf(stderr, "FINDING: spirv_load: the %s is not one line\n", kind);
    std::abort();
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  namespace sim = rayspace::sim;
  std::vector<std::uint32_t> words(size / 4);
  if (!words.empty()) std::memcpy(words.data(), data, words.size() * 4);
  sim::Program program;
  try {
    program = sim::Prepare(words, {}, "fuzz");
  } catch (const rayspace::InputError& e) {
    RequireOneLine(e.what(), "loader's refusal");
    return 0;
  }
  // Eight bindings of 64 words each, two workgroups, a short step limit: enough to run what the
  // module does, small enough for thousands of runs a second.
  std::vector<std::vector<std::uint32_t>> buffers(8, std::vector<std::uint32_t>(64, 0));
  sim::Dispatch d;
  d.groups[0] = 2;
  d.step_limit = 1u << 18;
  for (auto& b : buffers) d.bindings.push_back({reinterpret_cast<std::uint8_t*>(b.data()), b.size() * 4});
  sim::ExecStats stats;
  try {
    sim::Run(program, d, stats);
  } catch (const sim::SimError& e) {
    RequireOneLine(e.what(), "kernel's fault");
  } catch (const rayspace::InputError& e) {
    RequireOneLine(e.what(), "run's refusal");
  }
  return 0;
}
