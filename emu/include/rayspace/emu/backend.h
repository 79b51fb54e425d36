// The passes of a frame and of the ray-space hierarchy behind one interface per group, so the same
// frame runner and hierarchy tracer drive either the emulator or the Vulkan kernels, and the diff and
// replay tools run one pass on both with the same inputs.
//
// Lifecycle: a backend is created once per process (the Vulkan one owns its device), handed by
// reference to RenderFrame / MakeHierarchyTracer, and outlives them. Every method is a pure function
// of its arguments: it reads inputs, returns outputs, keeps no state between calls (beyond caches of
// immutable inputs). A backend that fails (a Vulkan error) throws BackendError naming the pass and the
// failed call.
#pragma once
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "rayspace/emu/calls.h"
#include "rayspace/emu/hierarchy.h"
#include "rayspace/emu/passes.h"

namespace rayspace::emu {

class BackendError : public std::runtime_error {
 public:
  // `checker`: the simulated device's checker whose finding failed the call ("racecheck", ...), or "";
  // `finding`: that finding's own text (what names the backend and pass around it).
  // `device_fault`: the device could not finish the call (a failed Vulkan call, the simulated GPU's step
  // limit), so no output was judged; otherwise the kernel's output broke its contract.
  explicit BackendError(const std::string& what, std::string checker = {}, std::string finding = {}, bool device_fault = false)
      : std::runtime_error(what), checker_(std::move(checker)), finding_(std::move(finding)), device_fault_(device_fault) {}
  const std::string& checker() const { return checker_; }
  const std::string& finding() const { return finding_; }
  bool device_fault() const { return device_fault_; }

 private:
  std::string checker_, finding_;
  bool device_fault_ = false;
};

// One virtual method per call (emu/calls.h), named like the call: `Result TraverseTop(const
// call::TraverseTop&)`. A pass's inputs are spelled once, in its call struct.
#define RS_DECLARE_CALL(C) virtual call::C::Result C(const call::C& c) = 0;
#define RS_FORWARD_CALL(C) call::C::Result C(const call::C& c) override { return t_.C(c); }

class FramePasses {
 public:
  virtual ~FramePasses() = default;
  virtual std::string Name() const = 0;
  // The name of the frame pass about to run (e.g. "raygen.shadow.b0"), for reports.
  virtual void Label(const std::string& /*pass*/) {}
  RS_FRAME_CALLS(RS_DECLARE_CALL)
};

class HierarchyPasses {
 public:
  virtual ~HierarchyPasses() = default;
  virtual std::string Name() const = 0;
  // The name of the tracer's sub-pass about to run (e.g. "traverse.L2.shadow.b0"), for reports.
  virtual void Label(const std::string& /*pass*/) {}
  RS_HIERARCHY_CALLS(RS_DECLARE_CALL)
};

// Forwards every pass to another backend (the emulator's by default): tools that change or observe
// one pass override just that one.
class ForwardingHierarchyPasses : public HierarchyPasses {
 public:
  explicit ForwardingHierarchyPasses(HierarchyPasses* target = nullptr);
  std::string Name() const override;
  void Label(const std::string& pass) override { t_.Label(pass); }
  RS_HIERARCHY_CALLS(RS_FORWARD_CALL)

 private:
  HierarchyPasses& t_;
};

// Runs a call on the group that has it (overloads for every call of both groups).
#define RS_RUN_FRAME_CALL(C) \
  inline call::C::Result RunCall(FramePasses& p, HierarchyPasses&, const call::C& c) { return p.C(c); }
#define RS_RUN_HIERARCHY_CALL(C) \
  inline call::C::Result RunCall(FramePasses&, HierarchyPasses& p, const call::C& c) { return p.C(c); }
RS_FRAME_CALLS(RS_RUN_FRAME_CALL)
RS_HIERARCHY_CALLS(RS_RUN_HIERARCHY_CALL)
#undef RS_RUN_FRAME_CALL
#undef RS_RUN_HIERARCHY_CALL

// The emulator's passes (emu/passes.h, emu/hierarchy.h).
FramePasses& EmuFramePasses();
HierarchyPasses& EmuHierarchyPasses();


}  // namespace rayspace::emu
