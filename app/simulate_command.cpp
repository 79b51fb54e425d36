#include "simulate_command.h"

#include <chrono>
#include <cstdio>
#include <optional>

#include "rayspace/error.h"

#include "rayspace/sim/export_run.h"

namespace rayspace::app {

ExitCode RunSimulate(const SimulateArgs& args) {
  const auto t0 = std::chrono::steady_clock::now();
  std::string error;
  const std::optional<sim::Checks> checks = sim::ParseChecks(args.sim_checks, error);
  if (!checks) ThrowInput("--sim-checks {}: {}", args.sim_checks, error);
  const std::optional<sim::DeviceModelChoice> model = sim::ParseDeviceModel(args.device_model, error);
  if (!model) ThrowInput("--device-model {}: {}", args.device_model, error);
  const std::optional<sim::SubgroupLayoutChoice> layout = sim::ParseSubgroupLayout(args.subgroup_layout, error);
  if (!layout) ThrowInput("--subgroup-layout {}: {}", args.subgroup_layout, error);
  sim::DeviceConfig device;
  device.layout = *layout;
  device.subgroup_size = args.subgroup_size;
  device.checks = *checks;
  device.arithmetic = *model;
  sim::ExportRun run;
  try {
    run = sim::RunExport(args.dir, device);
  } catch (const sim::SimError& e) {
    if (e.checker())
      std::fprintf(stderr, "rayspace simulate: %s: %s found a fault of the kernel: %s\n", args.dir.c_str(), sim::CheckerName(*e.checker()),
                   e.what());
    else
      std::fprintf(stderr, "rayspace simulate: %s: the kernel faulted: %s\n", args.dir.c_str(), e.what());
    return ExitCode::kWorkgroupFault;
  }
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf("rayspace simulate: %s on the simulated GPU (subgroup size %u): %llu dispatches, %llu workgroups, %.1f M lane-instructions in %.2f s\n",
              run.call.c_str(), args.subgroup_size, static_cast<unsigned long long>(run.dispatches),
              static_cast<unsigned long long>(run.stats.workgroups), run.stats.lane_instructions / 1e6, s);
  std::printf("  %-18s %10s %16s %10s %10s %12s\n", "kernel", "dispatches", "lane-instr (M)", "prepare s", "run s", "M lane-instr/s");
  for (const sim::KernelTiming& k : run.kernels)
    std::printf("  %-18s %10llu %16.2f %10.3f %10.3f %12.1f\n", k.kernel.c_str(), static_cast<unsigned long long>(k.dispatches),
                k.lane_instructions / 1e6, k.prepare_s, k.run_s, k.run_s > 0 ? k.lane_instructions / 1e6 / k.run_s : 0.0);
  for (const sim::ReadBackResult& r : run.reads)
    std::printf("  %s (%s): %s\n", r.file.c_str(), r.label.c_str(), r.equal ? "equal" : r.mismatch.c_str());
  if (run.Equal()) {
    std::printf("equal: every read-back has the expected bytes\n");
    return ExitCode::kOk;
  }
  std::fprintf(stderr, "rayspace simulate: %s: a read-back differs from the expected bytes\n", args.dir.c_str());
  return ExitCode::kDivergence;
}

}  // namespace rayspace::app
