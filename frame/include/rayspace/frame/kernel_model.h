// How the emulated kernels run: the workgroup schedule (--schedule), the workgroup checker
// (--check-workgroups) and planted faults on either side (--inject PASS:FAULT[@emu]).
#pragma once
#include <cstdint>
#include <map>
#include <set>
#include <string>

#include "rayspace/workgroup.h"
#include "rayspace/settings.h"

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
// Whether the options ask for the emulated kernels' workgroups: the checker on, or a schedule other
// than forward (an @emu fault asks too, through the Injection).
bool RequestsWorkgroupModel(const KernelModelArgs& args);

// --inject PASS[:FAULT][@emu]: FAULT is a number or a workgroup fault's name (pass_registry.h);
// "@emu" plants it in the emulated kernel instead of the Vulkan one; "none" (or "") plants nothing,
// which `replay` needs to run a call without the fault recorded with it. Bad specs are InputErrors
// listing what exists.
struct Injection {
  std::map<std::string, std::uint32_t> kernel, emu;
};
Injection ParseInject(const std::string& spec);

// What a run did that decides whether a planted fault can fire at all.
struct FaultFacts {
  std::set<std::string> passes;  // kernel passes the run called
  bool split = false;            // a buffer was split into parts or paged over bindings
  bool rows = false;             // a launch was folded into rows of workgroups
  bool scan = false;             // the reduction ran as a scan
};
// Why the fault `spec` (--inject, parsed into `injection`) could not fire in a run with these facts, or
// "" when it could.
std::string FaultCannotFire(const std::string& spec, const Injection& injection, const FaultFacts& facts);

// The emulator's workgroup model in force for the caller's scope: schedule, local size, subgroup size
// (the device's, or lavapipe's 8 without one), checking, the emulator-side faults, and whether the
// model was asked for (Settings::workgroup_model: traverse.compact then runs its workgroup mirror).
[[nodiscard]] ScopedSettings EmulatedKernels(const KernelModelArgs& args, std::uint32_t local_size, std::uint32_t subgroup_size,
                                             const Injection& injection);

}  // namespace rayspace::app
