#pragma once
#include "rayspace/exit_codes.h"

namespace rayspace::app {

// `rayspace devices`: every Vulkan device with each requirement met or not, the one render and diff
// would choose, and the comparison diff makes on it. kOk when a device meets every requirement,
// kBadInput (with one line on stderr) when none does.
ExitCode RunDevices();

}  // namespace rayspace::app
