#include "rayspace/reproduce/faithful_presets.h"

namespace rayspace::app {

std::vector<std::string> FaithfulPreset(const std::string& name) {
  // The thesis's Sponza as one object is a property of that scene, not of the method: --one-object
  // stays a switch of its own (`rayspace reproduce` sets it for Sponza).
  if (name == "thesis")
    return {"--hash-order", "polar-first", "--hash-bits", "8", "--shadow-bounces", "first", "--objects", "flat", "--cone-test", "printed"};
  if (name == "roger") return {"--objects", "flat", "--cone-test", "printed", "--leaf-test", "ray-sphere"};
  if (name == "none") return {};
  return {};
}

}  // namespace rayspace::app
