// The simulated GPU's configuration: everything a run on the simulator depends on beyond the kernel
// and its inputs. It travels with the backend that owns the simulated device (no process-wide state),
// so that two simulated devices in one process may differ.
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "rayspace/workgroup.h"

namespace rayspace::sim {

// The checkers (docs/simulator.md): each finding of the simulator is of one of them.
enum class Checker : std::uint8_t { kRacecheck, kInitcheck, kSynccheck, kMemcheck };
constexpr int kCheckerCount = 4;
const char* CheckerName(Checker c);  // "racecheck", ...

// A set of checkers, one bit per Checker.
struct Checks {
  std::uint8_t bits = 0xf;  // all on
  bool On(Checker c) const { return bits >> static_cast<int>(c) & 1u; }
  static Checks None() { return {0}; }
  std::string ToString() const;  // "all", "none" or "racecheck,memcheck"
};
// "all", "none" or a comma-separated list of checker names; nullopt (and `error`) for anything else.
std::optional<Checks> ParseChecks(std::string_view list, std::string& error);

// The simulated device's float arithmetic (docs/simulator.md, "Device models"): lavapipe's (every
// operation correctly rounded, nothing fused, denormals kept: the emulator's bits), or the
// worst-conformant device, whose loose operations each take another value Vulkan permits, drawn
// from a seed; worst-nearest is the same device with +, -, * and conversions rounded to nearest.
enum class DeviceModel : std::uint8_t { kLavapipe, kWorst, kWorstNearest };
struct DeviceModelChoice {
  DeviceModel model = DeviceModel::kLavapipe;
  std::uint64_t seed = 1;
  std::string ToString() const;  // "lavapipe", "worst:SEED" or "worst-nearest:SEED"
};
// "lavapipe", "worst" or "worst-nearest" (seed 1), or either with ":SEED"; nullopt (and `error`) for
// anything else.
std::optional<DeviceModelChoice> ParseDeviceModel(std::string_view text, std::string& error);

// How a workgroup's invocations fill its subgroups (docs/simulator.md, "Subgroup layouts"). Vulkan
// ties LocalInvocationIndex to no subgroup or lane, and without full subgroups (the kernels' pipelines
// do not require them) a subgroup may launch with lanes no invocation holds. linear is lavapipe's:
// subgroup k holds local indices k*S .. k*S+S-1 at lanes 0 .. S-1. shuffled deals the invocations to
// the (subgroup, lane) places of the linear layout in a seeded order; partial launches each subgroup
// with a seeded count of invocations between S/2 and S, in local order, at seeded lanes.
enum class SubgroupLayout : std::uint8_t { kLinear, kShuffled, kPartial };
struct SubgroupLayoutChoice {
  SubgroupLayout layout = SubgroupLayout::kLinear;
  std::uint64_t seed = 1;
  std::string kernel;  // only this kernel's dispatches ("": every kernel's); the others linear
  std::string ToString() const;  // "linear", "shuffled:SEED", "partial:SEED", then "@KERNEL" if any
};
// "linear", "shuffled", "partial" (seed 1), or the last two with ":SEED", each with "@KERNEL" to
// apply to that kernel alone; nullopt (and `error`) else.
std::optional<SubgroupLayoutChoice> ParseSubgroupLayout(std::string_view text, std::string& error);

struct DeviceConfig {
  std::uint32_t subgroup_size = 8;        // lavapipe's
  // The order of a dispatch's workgroups and, between two barriers, of a workgroup's subgroups:
  // forward, reverse, or a permutation drawn from the seed per dispatch and per interval.
  wg::Schedule schedule;
  std::uint64_t step_limit = 1ull << 34;  // lane-instructions of one workgroup before it counts as a hang
  // The checkers that run. One switched off lets the kernel go on as a lenient device would: an access
  // outside a binding reads zero and writes nothing, a division by zero gives zero, a divergent
  // barrier releases whoever waits; races and undefined reads go unreported.
  Checks checks;
  DeviceModelChoice arithmetic;
  SubgroupLayoutChoice layout;
};

}  // namespace rayspace::sim
