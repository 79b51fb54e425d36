// The emulator as a backend: each call runs the pass function that mirrors its kernel.
#include "rayspace/emu/backend.h"

#include "rayspace/emu/object_tree_traverse.h"

namespace rayspace::emu {
namespace {

// Every call C runs the emulator's Pass<C> (emu/passes.h, emu/hierarchy.h).
#define RS_EMU_CALL(C) call::C::Result C(const call::C& c) override { return Pass##C(c); }

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

}  // namespace

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
