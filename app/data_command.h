// `rayspace data check`: is the data root the one the bundled scenes were measured with?
#pragma once
#include <string>
#include <vector>

#include "rayspace/exit_codes.h"

namespace rayspace::app {

struct DataCheckArgs {
  std::string data;                 // the data root (default: $RAYSPACE_DATA)
  std::vector<std::string> scenes;  // scene JSON files or bundled scene names (default: every bundled scene)
};

// Prints one line per scene (ok, or each problem); kBadInput when any file is missing or differs.
ExitCode RunDataCheck(const DataCheckArgs& args);

}  // namespace rayspace::app
