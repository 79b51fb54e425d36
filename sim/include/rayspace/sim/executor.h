// The executor: one dispatch of a prepared kernel on the CPU. Invocations are grouped into subgroups
// that run in lockstep over active-lane masks: each step runs one segment (a basic block up to its
// terminator or a barrier) for every lane of the subgroup that stands at it, choosing the segment
// earliest in the function, so lanes that diverged reconverge at the merge block where the
// structured control flow joins. A barrier holds a subgroup until every subgroup of the workgroup
// reached it. Arithmetic is as lavapipe computes it: +, -, *, /, sqrt correctly rounded, nothing
// fused, denormals kept, min/max and the float-to-integer conversions as LAVAPIPE measures them.
#pragma once
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "rayspace/sim/device.h"
#include "rayspace/sim/program.h"

namespace rayspace::sim {

// A fault of the kernel found while running it (an access outside a binding, a division by zero, a
// barrier some invocations never reach, the step limit): the message names the kernel and its line.
// A checker's finding carries the checker; a fault no checker owns (the step limit, an instruction
// the simulator lacks) carries none.
class SimError : public std::runtime_error {
 public:
  explicit SimError(const std::string& what, std::optional<Checker> checker = std::nullopt)
      : std::runtime_error(what), checker_(checker) {}
  std::optional<Checker> checker() const { return checker_; }

 private:
  std::optional<Checker> checker_;
};

// A storage buffer bound to the dispatch: `bytes` is the descriptor's range (what OpArrayLength
// measures), of which the first `valid` bytes are the buffer's own (0: all); the rest are the host's
// guard words, which memcheck counts as outside the buffer.
struct Binding {
  std::uint8_t* data = nullptr;
  std::size_t bytes = 0;
  std::size_t valid = 0;
};

struct Dispatch {
  std::uint32_t groups[3] = {1, 1, 1};
  std::vector<Binding> bindings;          // by binding number (set 0)
  std::span<const std::uint8_t> push;     // the push-constant block
  std::uint32_t subgroup_size = 8;        // lavapipe's
  std::uint64_t step_limit = 1ull << 34;  // lane-instructions of one workgroup before it counts as a hang
  wg::Schedule schedule;                  // workgroup and subgroup order (DeviceConfig::schedule)
  std::uint64_t dispatch_index = 0;       // mixed into a random schedule's seed: each dispatch its own order
  Checks checks;                          // the checkers that run (DeviceConfig::checks)
  DeviceModelChoice arithmetic;           // DeviceConfig::arithmetic
  SubgroupLayoutChoice layout;            // DeviceConfig::layout
  std::uint8_t* coverage = nullptr;       // one byte per instruction of Program::code, set when it runs (coverage.h)
};

struct ExecStats {
  std::uint64_t lane_instructions = 0;  // instructions executed, times the lanes active in each
  std::uint64_t workgroups = 0;
};

// Runs every workgroup of the dispatch in the schedule's order (forward: by linear index). Throws
// SimError on a fault.
void Run(const Program& program, const Dispatch& dispatch, ExecStats& stats);

}  // namespace rayspace::sim
