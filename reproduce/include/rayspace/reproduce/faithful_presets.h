// The --faithful presets as lists of switches: data only, so that `rayspace reproduce` can name a
// preset's contents in its results' keys without the command-line code (faithful_args.h).
#pragma once
#include <string>
#include <vector>

namespace rayspace::app {

// A preset's switches, as command-line words ("--hash-order", "polar-first", "--one-object", ...): the
// one list --faithful applies and --help prints. An unknown name: empty.
std::vector<std::string> FaithfulPreset(const std::string& name);

}  // namespace rayspace::app
