#include "data_check.h"

#include "rayspace/error.h"
#include "rayspace/input_file.h"

namespace rayspace::reproduce {

void CheckSceneData(const std::vector<std::filesystem::path>& scenes, const std::filesystem::path& data_root) {
  (void)data_root;
  for (const std::filesystem::path& s : scenes)
    if (const std::string why = NotRegularFile(s.string()); !why.empty())
      ThrowInput("{}: cannot open scene file: it {} (--scenes names the directory of the scene files)", s.string(), why);
}

}  // namespace rayspace::reproduce
