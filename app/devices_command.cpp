#include "devices_command.h"

#include <cstdio>
#include <string>

#include "rayspace/error.h"
#include "rayspace/gpu/float_controls.h"
#include "rayspace/gpu/requirements.h"

namespace rayspace::app {
namespace {

// What `diff --compare auto` does on a device. lavapipe's float operations are correctly rounded
// (measured, docs/gpu.md), so its kernels give the emulator's bits; elsewhere Vulkan allows division
// within 2.5 ULP and a square root derived from the inverse square root, so the relaxed device model
// decides whether a differing word is one the spec permits.
std::string ComparisonModel(const vk::DeviceReport& d) {
  if (d.driver_id == VK_DRIVER_ID_MESA_LLVMPIPE)
    return "bitwise: every buffer must equal the emulator's (lavapipe rounds +, -, *, /, sqrt correctly)";
  return "relaxed: Vulkan lets this device round division and square root loosely, so a differing word passes "
         "when a conformant device may compute it (docs/numerics.md); --strict-math makes it bitwise";
}

}  // namespace

ExitCode RunDevices() {
  int preferred = -1;
  const std::vector<vk::DeviceReport> devices = vk::DescribeDevices(preferred);
  if (!devices.empty())  // every device reports the same requirement names
    if (const std::string unknown = vk::UnknownLack(devices.front().requirements); !unknown.empty())
      ThrowInput("--device-lacks '{}': not a requirement (rayspace devices lists them)", unknown);
  std::printf("rayspace devices: %zu Vulkan device(s)\n", devices.size());
  bool usable = false;
  for (const vk::DeviceReport& d : devices) {
    const bool ok = vk::Unmet(d.requirements).empty();
    usable |= ok;
    std::printf("\n  --device %d  %s  (%s; %s)%s\n", d.index, d.name.c_str(), d.type.c_str(), d.driver.c_str(),
                d.index == preferred ? "  <- used without --device" : "");
    for (const vk::Requirement& r : d.requirements)
      std::printf("    %-7s %-37s need %-10s have %-13s %s\n", r.met ? "met" : (r.optional ? "absent" : "NOT MET"), r.name.c_str(), r.need.c_str(),
                  r.have.c_str(), r.why.c_str());
    std::printf("    float controls (32-bit): DenormPreserve %s, DenormFlushToZero %s, RoundingModeRTE %s\n",
                d.denorm_preserve ? "yes" : "no", d.denorm_flush ? "yes" : "no", d.round_to_nearest ? "yes" : "no");
    std::printf("    the kernels request: %s (what the device offers of DenormPreserve and RoundingModeRTE)\n",
                vk::FloatControls{d.denorm_preserve, d.round_to_nearest}.Describe().c_str());
    // lavapipe's subgroup is one SIMD register of 32-bit lanes: its width is the environment's choice.
    if (d.driver_id == VK_DRIVER_ID_MESA_LLVMPIPE)
      std::printf("    subgroup size: LP_NATIVE_VECTOR_WIDTH=128, 256 or 512 in the environment gives 4, 8 or 16 lanes\n");
    std::printf("    %s\n", ok ? "usable" : "not usable: rayspace refuses it, naming what is missing");
    std::printf("    diff compares: %s\n", ComparisonModel(d).c_str());
  }
  if (!usable) {
    std::fprintf(stderr, "rayspace: error: no Vulkan device meets rayspace's requirements (see above)\n");
    return ExitCode::kBadInput;
  }
  return ExitCode::kOk;
}

}  // namespace rayspace::app
