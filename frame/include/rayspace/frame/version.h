// `rayspace --version`: the version, the commit it was built from, the backends built in and the
// libraries (with the versions their headers declare) it was built against.
#pragma once
#include <string>

#include <nlohmann/json_fwd.hpp>

namespace rayspace::app {

std::string VersionText();
// The commit this binary was built from (as --version prints it).
std::string BuildCommit();

// The command line as given (main sets it once), for the JSON files a run writes.
void SetArguments(int argc, char** argv);
// What made a JSON file, so that a result can be traced to its build and its options: adds
// "rayspace_version", "commit" and "arguments" (argv as given, the program's name first).
void AddProvenance(nlohmann::json& j);
// AddProvenance without the arguments: for a report that must not depend on how it was asked for
// (mutate's, which shards merge into).
void AddVersion(nlohmann::json& j);

}  // namespace rayspace::app
