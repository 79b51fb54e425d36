// Output names that come from an input: a scene's "name" names render's default image and the
// accuracy report's files. An input file must never choose where outputs go beyond a plain file name
// in the directory the user chose.
#pragma once
#include <string>
#include <string_view>

#include "rayspace/scene.h"

namespace rayspace {

// The scene's name as the stem of an output file; an InputError naming the scene file, ending with
// `remedy` (what the user can do instead), when the name is empty, "." or "..", holds a path
// separator or a control character, or is longer than 200 bytes.
std::string SceneOutputStem(const Scene& scene, std::string_view remedy);

}  // namespace rayspace
