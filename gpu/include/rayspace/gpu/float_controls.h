// The float controls a device offers beyond Vulkan's minimum, requested in every kernel it runs:
// 32-bit denormals preserved (DenormPreserve) and round-to-nearest-even (RoundingModeRTE), each only
// where the device supports it (shaderDenormPreserveFloat32, shaderRoundingModeRTEFloat32). Without
// them a device may flush denormals and round + - * toward zero; with them it computes the
// emulator's arithmetic. The kernels are compiled without either, so the request is made by adding
// the capability and execution mode to the module when its pipeline is made.
#pragma once
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace rayspace::vk {

struct FloatControls {
  bool denorm_preserve = false;   // DenormPreserve 32
  bool round_to_nearest = false;  // RoundingModeRTE 32
  // "DenormPreserve, RoundingModeRTE" (the requested ones), or "none".
  std::string Describe() const;
};

// `spirv` with the requested 32-bit float controls declared for its entry points (a module that
// already declares one keeps it as it is). A module that is not SPIR-V comes back unchanged.
std::vector<std::uint32_t> WithFloatControls(std::span<const std::uint32_t> spirv, FloatControls want);

// The float controls a module declares for 32-bit floats (for tests and reports).
FloatControls DeclaredFloatControls(std::span<const std::uint32_t> spirv);

}  // namespace rayspace::vk
