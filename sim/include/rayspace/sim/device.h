// The simulated GPU's configuration: everything a run on the simulator depends on beyond the kernel
// and its inputs. It travels with the backend that owns the simulated device (no process-wide state),
// so that two simulated devices in one process may differ.
#pragma once
#include <cstdint>

#include "rayspace/workgroup.h"

namespace rayspace::sim {

struct DeviceConfig {
  std::uint32_t subgroup_size = 8;        // lavapipe's
  // The order of a dispatch's workgroups and, between two barriers, of a workgroup's subgroups:
  // forward, reverse, or a permutation drawn from the seed per dispatch and per interval.
  wg::Schedule schedule;
  std::uint64_t step_limit = 1ull << 34;  // lane-instructions before a dispatch counts as a hang
};

}  // namespace rayspace::sim
