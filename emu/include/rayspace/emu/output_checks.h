// What a backend hands back, checked where it returns it. A device's kernel can return any bits; the
// host indexes its arrays with the indices and counts among them (pairs, primitive and material ids,
// chunk bounds, ray counts), so each is checked against the call's own inputs before anything reads
// with it. A bad value is a DeviceOutputError naming the call, the backend, the output buffer and its
// first bad element; never a read past an array, an internal check failing later, or "bad input" in
// the next pass. The checks bound values (an index in range, a count that agrees with the inputs);
// whether a value is right is the diff's question, which compares the outputs first.
#pragma once
#include <stdexcept>
#include <string>
#include <memory>
#include <string_view>

#include "rayspace/emu/calls.h"

namespace rayspace::emu {

class FramePasses;
class HierarchyPasses;

class DeviceOutputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Who returned the outputs: the backend's name and the pass label it ran under (e.g.
// "traverse.L2.shadow.b0"; may be empty).
struct OutputSource {
  std::string_view backend;
  std::string_view label;
};

// Throws DeviceOutputError when call c's outputs (its result r, null for a void result, and its
// in-place arrays) hold an index out of range or a count that disagrees with c's inputs. c's inputs
// are taken as valid (emu::CheckInputs).
#define RS_DECLARE_OUTPUT_CHECK(C) void CheckOutputs(const call::C& c, const call::C::Result* r, const OutputSource& from);
RS_FRAME_CALLS(RS_DECLARE_OUTPUT_CHECK)
RS_HIERARCHY_CALLS(RS_DECLARE_OUTPUT_CHECK)
#undef RS_DECLARE_OUTPUT_CHECK

// A backend whose every call's outputs are checked (CheckOutputs) before they are returned. The frame
// runner and the hierarchy tracer wrap every backend but the emulator's own in it.
std::unique_ptr<FramePasses> CheckedFramePasses(FramePasses& target);
std::unique_ptr<HierarchyPasses> CheckedHierarchyPasses(HierarchyPasses& target);

}  // namespace rayspace::emu
