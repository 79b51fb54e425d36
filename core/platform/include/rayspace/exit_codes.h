// The exit codes of every rayspace command, stated once: `--help` prints this table (ExitCodeHelp),
// README.md's and docs/usage.md's exit-code tables say the same, and tests/cli_exit_codes.cmake checks all three.
#pragma once
#include <string>

#include <fmt/format.h>

namespace rayspace {

enum class ExitCode : int {
  kOk = 0,
  kInternal = 1,
  kBadInput = 2,
  kOracleMismatch = 3,
  kDivergence = 4,
  kNotReproduced = 5,
  kWorkgroupFault = 6,
  kBackendFault = 7,
};

struct ExitCodeMeaning {
  ExitCode code;
  const char* meaning;
};

inline constexpr ExitCodeMeaning kExitCodes[] = {
    {ExitCode::kOk, "success"},
    {ExitCode::kInternal, "internal failure"},
    {ExitCode::kBadInput, "bad input (one line on stderr naming the file and field or line)"},
    {ExitCode::kOracleMismatch, "render: the oracle found rays the frame got wrong"},
    {ExitCode::kDivergence, "diff or replay: a pass diverged; simulate: a read-back differs from the expected bytes; bench: configurations of one tracer gave different frames"},
    {ExitCode::kNotReproduced, "replay: the recorded comparison was not reproduced"},
    {ExitCode::kWorkgroupFault, "render, diff or replay: the workgroup checker found a race, a read of an unwritten shared word or a divergent barrier in an emulated kernel, or a checker of the simulated GPU in a kernel; simulate: the kernel faulted on the simulated GPU"},
    {ExitCode::kBackendFault, "render, diff or replay: the device could not finish a pass (a failed Vulkan call, the simulated GPU's step limit): nothing was compared from that pass on"},
};

// The value main() returns.
constexpr int ToInt(ExitCode c) { return static_cast<int>(c); }

// The help footer: one line per code.
inline std::string ExitCodeHelp() {
  std::string s = "Exit codes:";
  for (const ExitCodeMeaning& e : kExitCodes) s += fmt::format("\n  {}  {}", ToInt(e.code), e.meaning);
  return s;
}

}  // namespace rayspace
