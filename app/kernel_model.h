// How the emulated kernels run: the workgroup schedule (--schedule), the workgroup checker
// (--check-workgroups) and planted faults on either side (--inject PASS:FAULT[@emu]).
#pragma once
#include <cstdint>
#include <map>
#include <string>

#include "rayspace/workgroup.h"

namespace CLI {
class App;
}

namespace rayspace::app {

// "forward", "reverse" or "random[:SEED]" (seed a decimal number, default 1); anything else is an
// InputError naming --schedule.
wg::Schedule ParseSchedule(const std::string& spec);
std::string ToString(const wg::Schedule& s);

struct KernelModelArgs {
  std::string schedule = "forward";
  bool check = false;  // --check-workgroups (also on when a fault is planted on the emulator's side)
  static KernelModelArgs Checked() {
    KernelModelArgs a;
    a.check = true;
    return a;
  }
};
void AddKernelModelOptions(CLI::App& command, KernelModelArgs& args);
// Whether the options ask for the emulated kernels' workgroups: the checker on, or a schedule other
// than forward (an @emu fault asks too, through the Injection).
bool RequestsWorkgroupModel(const KernelModelArgs& args);

// --inject PASS[:FAULT][@emu]: FAULT is a number or a workgroup fault's name (pass_registry.h);
// "@emu" plants it in the emulated kernel instead of the Vulkan one. Bad specs are InputErrors listing
// what exists.
struct Injection {
  std::map<std::string, std::uint32_t> kernel, emu;
};
Injection ParseInject(const std::string& spec);

// Sets the emulator's workgroup model for this process: schedule, local size, subgroup size (the
// device's, or lavapipe's 8 without one), checking, the emulator-side faults, and whether the model
// was asked for (emu::SetWorkgroupModel: traverse.compact then runs its workgroup mirror).
void ConfigureEmulatedKernels(const KernelModelArgs& args, std::uint32_t local_size, std::uint32_t subgroup_size,
                              const Injection& injection);

}  // namespace rayspace::app
