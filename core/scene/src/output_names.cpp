#include "rayspace/output_names.h"

#include "rayspace/error.h"
#include "rayspace/json_text.h"

namespace rayspace {

std::string SceneOutputStem(const Scene& scene, std::string_view remedy) {
  const std::string& name = scene.name;
  const char* why = nullptr;
  if (name.empty()) why = "it is empty";
  else if (name == "." || name == "..") why = "it names a directory";
  else if (name.size() > 200) why = "it is longer than 200 bytes";
  for (const char c : name) {
    if (why) break;
    if (c == '/' || c == '\\') why = "it holds a path separator";
    else if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) why = "it holds a control character";
  }
  if (why)
    ThrowInput("{}: the scene's \"name\" '{}' cannot name an output file: {}; {}", EscapeInvalidUtf8(scene.path.string()),
               EscapeInvalidUtf8(name.substr(0, 60)), why, remedy);
  return name;
}

}  // namespace rayspace
