// The settings a run is made with: thread count and schedule, the workgroup model's checking and
// device shape, the emulated kernels' ISA and planted faults, the Vulkan side's options. They are a
// value, never process-wide state. The settings in force belong to the calling thread: a command or a
// library call installs its own for a scope with ScopedSettings, and ParallelFor carries the caller's
// settings into its workers, so two frames started on two threads with different settings run as
// they would alone (tests/settings_test.cpp). A thread that installed nothing sees Settings{}.
#pragma once
#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <type_traits>
#include <utility>

namespace rayspace {

namespace vk {
class Observer;
}

// The widest vector instructions a CPU path runs on (the emulator's cone and intersection lanes).
enum class Isa { kScalar, kAvx2, kAvx512 };

namespace wg {
enum class Order { kForward, kReverse, kRandom };
// The order the invocations of each phase run in. kRandom draws a fresh permutation per (workgroup,
// phase) from the seed, so a run is reproducible for any thread count.
struct Schedule {
  Order order = Order::kForward;
  std::uint64_t seed = 0;
};
}  // namespace wg

// How the Vulkan instance is validated: as the RAYSPACE_VALIDATE environment variable says (unset or
// "0": not, "gpu": with GPU-assisted validation, anything else: synchronization validation), or as
// the command asked (--validate asks for both).
enum class Validation { kFromEnvironment, kOff, kSynchronization, kGpuAssisted };

struct Settings {
  // ParallelFor: threads (0 = OpenMP's default) and elements per scheduling chunk (0 = an even static
  // split; tests vary it to prove a pass independent of the schedule).
  int threads = 0;
  std::size_t chunk = 0;

  // The workgroup model (rayspace/workgroup.h): the invocation order of each phase, whether shared
  // memory accesses are checked, and the device shape of dispatches that do not set their own (local
  // size 1..1024, subgroup size a power of two 1..128; lavapipe's subgroup is 8).
  wg::Schedule schedule;
  bool check = true;
  std::uint32_t local_size = 64;
  std::uint32_t subgroup_size = 8;

  // The emulated kernels: run the passes' workgroup mirrors instead of their fast paths; planted
  // faults (pass name -> the registry's fault number); the ISA of the fused levels and of the
  // intersection lanes (unset, or one this CPU cannot run: the widest it can).
  bool workgroup_model = false;
  std::map<std::string, std::uint32_t, std::less<>> emu_faults;
  std::optional<Isa> fused_isa, intersect_isa;

  // Test hooks of the emulator (each documented where it is read): an object-tree traversal fault
  // (emu::TreeFault), the fused path's and the grid lanes' planted faults, and the host cull margin
  // (unset: emu::cone::kCullMargin).
  std::uint32_t tree_fault = 0;
  bool fused_fault = false;
  bool grid_lanes_fault = false;
  std::optional<double> cull_margin;

  // The Vulkan side: --strict-math for kernels made from here on; new buffers filled with the
  // poison word; validation; devices made to look as if they lacked these requirements or limits
  // (--device-lacks); an observer of buffers and dispatches for contexts created from here on.
  bool strict_math = false;
  bool poison_new_buffers = true;
  Validation validation = Validation::kFromEnvironment;
  std::map<std::string, std::uint64_t> device_lacks;
  vk::Observer* observer = nullptr;

  // Where the fused path counts the top-level slots its group cull removed (nullptr: nowhere).
  std::uint64_t* culled_slots = nullptr;

  // RS_CHECK failures throw CheckFailure instead of aborting (the CLI reports them as errors).
  bool check_failures_throw = false;
};

// The settings in force on the calling thread.
const Settings& CurrentSettings();

// Installs settings on the calling thread until the end of the scope, then restores the outer ones.
// Refuses (RS_CHECK) a local or subgroup size out of range. Not copyable; scopes nest.
class ScopedSettings {
 public:
  explicit ScopedSettings(Settings settings);
  // The settings in force, changed by `edit`: ScopedSettings s([](Settings& x) { x.threads = 2; });
  template <class Edit, class = std::enable_if_t<std::is_invocable_v<Edit, Settings&>>>
  explicit ScopedSettings(Edit&& edit) : ScopedSettings(Edited(std::forward<Edit>(edit))) {}
  ~ScopedSettings();
  ScopedSettings(const ScopedSettings&) = delete;
  ScopedSettings& operator=(const ScopedSettings&) = delete;

 private:
  template <class Edit>
  static Settings Edited(Edit&& edit) {
    Settings s = CurrentSettings();
    edit(s);
    return s;
  }
  Settings settings_;
  const Settings* outer_;
};

// Puts settings someone else owns in force on the calling thread until the end of the scope: how a
// worker (ParallelFor's, a job runner's) takes its caller's settings. They must outlive the scope.
class SettingsInForce {
 public:
  explicit SettingsInForce(const Settings& settings);
  ~SettingsInForce();
  SettingsInForce(const SettingsInForce&) = delete;
  SettingsInForce& operator=(const SettingsInForce&) = delete;

 private:
  const Settings* outer_;
};

}  // namespace rayspace
