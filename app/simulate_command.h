// `rayspace simulate DIR`: an exported reproducer run on the simulated GPU (docs/simulator.md).
#pragma once
#include <cstdint>
#include <string>

#include "rayspace/exit_codes.h"

namespace rayspace::app {

struct SimulateArgs {
  std::string dir;
  std::uint32_t subgroup_size = 8;
  std::string sim_checks = "all";  // --sim-checks
  std::string device_model = "lavapipe";  // --device-model
  std::string subgroup_layout = "linear";  // --subgroup-layout
};

ExitCode RunSimulate(const SimulateArgs& args);

}  // namespace rayspace::app
