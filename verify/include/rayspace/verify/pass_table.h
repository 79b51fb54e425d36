// Every pass method of emu/backend.h as a function from a BufferSet of inputs to a BufferSet of
// outputs on a given backend. The diff runs a method on both backends through this table, and replay
// runs a saved call through the same entry, so both see exactly the same inputs.
#pragma once
#include <functional>
#include <set>
#include <string>
#include <vector>

#include "rayspace/emu/backend.h"
#include "rayspace/verify/buffer_set.h"

namespace rayspace::verify {

struct Backends {
  emu::FramePasses& frame;
  emu::HierarchyPasses& hierarchy;
};

struct PassMethod {
  std::string method;  // e.g. "traverse.top"
  // The kernel pass a call belongs to (the name `diff --inject` takes), e.g. "raygen.shadow".
  std::function<std::string(const BufferSet& in)> pass;
  // Outputs that later passes use as indices or counts: when they differ the diff must stop.
  std::set<std::string> index_outputs;
  std::function<BufferSet(const BufferSet& in, Backends& b)> run;
};

const std::vector<PassMethod>& PassMethods();
// Throws InputError naming the method and the known ones.
const PassMethod& FindPassMethod(const std::string& method);

}  // namespace rayspace::verify
