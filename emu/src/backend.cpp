// The emulator as a backend: each call runs the pass function that mirrors its kernel.
#include "rayspace/emu/backend.h"
#include "rayspace/emu/grid/grid.h"

#include "rayspace/emu/object_tree_traverse.h"
#include "rayspace/emu/output_checks.h"
#include "rayspace/emu/tl/heads.h"
#include "rayspace/emu/tl/tl.h"
#include "rayspace/emu/workgroup_ops.h"

namespace rayspace::emu {
namespace {

// Every call C runs the emulator's Pass<C> (emu/passes.h, emu/hierarchy.h). With an @emu fault
// planted, an emulated kernel's outputs may be garbage, and the passes after it would index with
// them: each call then checks its inputs against its contract first (emu/calls.h, CheckInputs), so
// the run stops with an InputError naming the call and the element instead of reading out of bounds.
// A render without faults skips the checks (its inputs come from passes that keep their contracts).
#define RS_EMU_CALL(C)                          \
  call::C::Result C(const call::C& c) override { \
    if (AnyEmuFault()) CheckInputs(c);          \
    return Pass##C(c);                          \
  }

class EmuFrame final : public FramePasses {
 public:
  std::string Name() const override { return "emu"; }
  RS_FRAME_CALLS(RS_EMU_CALL)
};

class EmuHierarchy final : public HierarchyPasses {
 public:
  std::string Name() const override { return "emu"; }
  RS_HIERARCHY_CALLS(RS_EMU_CALL)
};

// Runs a call on the target and checks its outputs before returning them (emu/output_checks.h).
template <typename C, typename Run>
typename C::Result CheckedRun(const C& c, const std::string& backend, const std::string& label, Run&& run) {
  const OutputSource from{backend, label};
  if constexpr (std::is_void_v<typename C::Result>) {
    run();
    CheckOutputs(c, nullptr, from);
  } else {
    typename C::Result r = run();
    CheckOutputs(c, &r, from);
    return r;
  }
}

#define RS_CHECKED_CALL(C) \
  call::C::Result C(const call::C& c) override { return CheckedRun(c, t_.Name(), label_, [&] { return t_.C(c); }); }

class CheckedFrame final : public FramePasses {
 public:
  explicit CheckedFrame(FramePasses& t) : t_(t) {}
  std::string Name() const override { return t_.Name(); }
  void Label(const std::string& pass) override { label_ = pass, t_.Label(pass); }
  RS_FRAME_CALLS(RS_CHECKED_CALL)

 private:
  FramePasses& t_;
  std::string label_;
};

class CheckedHierarchy final : public HierarchyPasses {
 public:
  explicit CheckedHierarchy(HierarchyPasses& t) : t_(t) {}
  std::string Name() const override { return t_.Name(); }
  void Label(const std::string& pass) override { label_ = pass, t_.Label(pass); }
  RS_HIERARCHY_CALLS(RS_CHECKED_CALL)

 private:
  HierarchyPasses& t_;
  std::string label_;
};

}  // namespace

std::unique_ptr<FramePasses> CheckedFramePasses(FramePasses& target) { return std::make_unique<CheckedFrame>(target); }
std::unique_ptr<HierarchyPasses> CheckedHierarchyPasses(HierarchyPasses& target) { return std::make_unique<CheckedHierarchy>(target); }

ForwardingHierarchyPasses::ForwardingHierarchyPasses(HierarchyPasses* target)
    : t_(target ? *target : EmuHierarchyPasses()) {}

std::string ForwardingHierarchyPasses::Name() const { return t_.Name(); }

FramePasses& EmuFramePasses() {
  static EmuFrame f;
  return f;
}

HierarchyPasses& EmuHierarchyPasses() {
  static EmuHierarchy h;
  return h;
}

}  // namespace rayspace::emu
