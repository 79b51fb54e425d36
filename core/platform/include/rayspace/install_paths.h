// Where the files rayspace reads at run time live: the kernels' GLSL (a user kernel includes their
// .glsl files and the contract headers; `mutate` rewrites the kernels themselves), the bundled scenes
// and the list of explained mutation survivors.
//
// An installed tree keeps them under its prefix (share/rayspace/, include/); a binary run from the
// build tree reads the source tree it was configured from. Nothing here is cached or settable: each
// caller asks with the prefix it was given, so two configurations in one process may differ.
#pragma once
#include <filesystem>
#include <string>

namespace rayspace {

struct DataPaths {
  std::filesystem::path shaders;    // the kernels (*.comp) and their includes (*.glsl)
  std::filesystem::path includes;   // the root of the contract headers (rayspace/layout.h, ...)
  std::filesystem::path scenes;     // the bundled scene files
  std::filesystem::path survivors;  // mutation-survivors.json
  std::string where;                // "install PREFIX" or "source tree DIR", for messages
};

// `prefix` non-empty: the install under it. Empty: the install that holds the running executable
// (<prefix>/bin/...) if it has rayspace's data, else the source tree this build came from. Does not
// check that the files exist; a caller that misses one names the path and `where`.
DataPaths FindDataPaths(const std::filesystem::path& prefix = {});

}  // namespace rayspace
