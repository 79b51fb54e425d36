// The relaxed device model (docs/numerics.md, "The relaxed device model"): for a pass call whose
// outputs differ between the emulator and a device, does every differing element hold a value some
// conformant Vulkan device may compute from the same inputs (division within 2.5 ULP, square root
// from a 2-ULP inversesqrt, denormals possibly flushed), or is one beyond what the spec allows?
//
// Most passes with float arithmetic the spec leaves loose have a model (raygen, intersect and
// intersect.tree, hash, surfaces, shade, build, traverse and traverse.compact, the object tree's
// tree.*, resolve). Each re-evaluates a differing element in SpecReal (spec_real.h) through the
// emulator's own templated math, so the model and the emulated pass cannot drift apart. The integer passes compute only what
// the spec makes exact on every device, and their differences are bugs on any device; tl.* and the
// grids' passes have no model yet (docs/numerics.md).
#pragma once
#include <string>

#include "rayspace/verify/buffer_set.h"

namespace rayspace::verify {

struct SpecVerdict {
  bool modelled = false;   // the pass has a relaxed model
  std::size_t within = 0;  // differing elements a conformant device may produce
  std::size_t beyond = 0;  // differing elements no conformant device produces from these inputs
  std::string first_beyond;  // the first of those, with the permitted range
  bool AllWithin() const { return modelled && beyond == 0; }
  std::string Summary() const;
};

// Classifies the differences between `expected` (the emulator's outputs) and `actual` for a call of
// `method` (pass_table.h) on inputs `in`. `flush_denormals`: the device may flush denormals.
SpecVerdict ClassifyWithinSpec(const std::string& method, const BufferSet& in, const BufferSet& expected,
                               const BufferSet& actual, bool flush_denormals = true);

}  // namespace rayspace::verify
