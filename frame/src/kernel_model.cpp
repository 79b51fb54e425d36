#include "rayspace/frame/kernel_model.h"

#include <vector>

#include <fmt/format.h>

#include "rayspace/emu/workgroup_ops.h"
#include "rayspace/error.h"
#include "rayspace/pass_registry.h"

namespace rayspace::app {

wg::Schedule ParseSchedule(const std::string& spec) {
  if (spec == "forward") return {wg::Order::kForward, 0};
  if (spec == "reverse") return {wg::Order::kReverse, 0};
  if (spec == "random") return {wg::Order::kRandom, 1};
  if (spec.rfind("random:", 0) == 0) {
    const std::string seed = spec.substr(7);
    if (!seed.empty() && seed.size() <= 19 && seed.find_first_not_of("0123456789") == std::string::npos)
      return {wg::Order::kRandom, std::stoull(seed)};
  }
  ThrowInput("--schedule '{}': expected forward, reverse or random[:SEED] (SEED a decimal number)", spec);
}

std::string ToString(const wg::Schedule& s) {
  switch (s.order) {
    case wg::Order::kForward: return "forward";
    case wg::Order::kReverse: return "reverse";
    case wg::Order::kRandom: return fmt::format("random:{}", s.seed);
  }
  return "?";
}

bool RequestsWorkgroupModel(const KernelModelArgs& args) {
  return args.check || ParseSchedule(args.schedule).order != wg::Order::kForward;
}

namespace {

// FAULT of PASS:FAULT: a number or a name the pass lists.
std::uint32_t FaultNumber(const PassSpec& p, const std::string& fault, const std::string& spec) {
  std::string known;
  for (const FaultSpec& f : p.faults) {
    const std::string label = f.name.empty() ? std::to_string(f.number) : fmt::format("{} ({})", f.number, f.name);
    known += (known.empty() ? "" : ", ") + label;
    if (fault == std::to_string(f.number) || (!f.name.empty() && fault == f.name)) return f.number;
  }
  ThrowInput("--inject '{}': {} has faults {}", spec, p.name, known);
}

// "traverse.compact:1 to 4": the passes' own faults their emulated kernels mirror.
std::string EmulatedOwnFaults() {
  std::string list;
  for (const PassSpec& p : kPasses) {
    std::vector<std::uint32_t> n;
    for (const FaultSpec& f : p.faults)
      if (f.emu) n.push_back(f.number);
    if (n.empty()) continue;
    list += fmt::format("{}{}:{}{}", list.empty() ? "" : ", ", p.name, n.front(), n.size() > 1 ? fmt::format(" to {}", n.back()) : "");
  }
  return list;
}

}  // namespace

Injection ParseInject(const std::string& spec) {
  Injection in;
  if (spec.empty() || spec == "none") return in;
  std::string body = spec;
  bool emu = false;
  if (const auto at = body.rfind('@'); at != std::string::npos) {
    if (body.substr(at + 1) != "emu") ThrowInput("--inject '{}': the side after '@' must be 'emu'", spec);
    body = body.substr(0, at);
    emu = true;
  }
  const auto colon = body.find(':');
  const std::string pass = body.substr(0, colon);
  const std::string fault = colon == std::string::npos ? std::string("1") : body.substr(colon + 1);
  std::string known;
  for (const PassSpec& p : kPasses) {
    known += (known.empty() ? "" : ", ") + std::string(p.name);
    if (p.name != pass) continue;
    const std::uint32_t n = FaultNumber(p, fault, spec);
    if (emu) {
      bool mirrored = false;
      for (const FaultSpec& f : p.faults) mirrored |= f.number == n && ((!f.name.empty() && !f.kernel_only) || f.emu);
      if (!mirrored)
        ThrowInput("--inject '{}': only the workgroup faults (named ones but global-race, out-of-bounds and undefined-value, which "
                   "live in the kernel alone) and {} can be planted on the emulator's side",
                   spec, EmulatedOwnFaults());
      in.emu[pass] = n;
    } else {
      in.kernel[pass] = n;
    }
    return in;
  }
  ThrowInput("--inject '{}': no kernel named '{}'; kernels: {}", spec, pass, known);
}

std::string FaultCannotFire(const std::string& spec, const Injection& injection, const FaultFacts& facts) {
  for (const auto* side : {&injection.kernel, &injection.emu}) {
    for (const auto& [pass, number] : *side) {
      if (!facts.passes.count(pass)) return fmt::format("the planted fault {} cannot fire: pass {} did not run", spec, pass);
      const std::optional<PassId> id = FindPass(pass);
      if (!id) continue;
      for (const FaultSpec& f : Pass(*id).faults) {
        if (f.number != number) continue;
        if (f.needs == FaultNeeds::kSplit && !facts.split)
          return fmt::format("the planted fault {} cannot fire: no buffer was split or paged (give --split-bytes)", spec);
        if (f.needs == FaultNeeds::kRows && !facts.rows)
          return fmt::format("the planted fault {} cannot fire: no launch was folded into rows (give --max-groups)", spec);
        if (f.needs == FaultNeeds::kScanReduction && !facts.scan)
          return fmt::format("the planted fault {} cannot fire: the reduction did not run as a scan (give --reduction scan)", spec);
      }
    }
  }
  return {};
}

ScopedSettings EmulatedKernels(const KernelModelArgs& args, std::uint32_t local_size, std::uint32_t subgroup_size,
                               const Injection& injection) {
  return ScopedSettings([&](Settings& s) {
    s.schedule = ParseSchedule(args.schedule);
    s.local_size = local_size;
    s.subgroup_size = subgroup_size == 0 ? 8u : subgroup_size;
    s.check = args.check || !injection.emu.empty();
    s.emu_faults = {injection.emu.begin(), injection.emu.end()};
    s.workgroup_model = RequestsWorkgroupModel(args) || !injection.emu.empty();
  });
}

}  // namespace rayspace::app
