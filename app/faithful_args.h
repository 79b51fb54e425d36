// Switches that make the hierarchy work as the CRSH thesis printed it (docs/hierarchy.md, "Faithful to
// the thesis"): render, diff and bench register them with one function, so their defaults agree.
#pragma once
#include <string>

#include "rayspace/emu/hierarchy.h"

namespace CLI {
class App;
}

namespace rayspace::app {

struct FaithfulArgs {
  std::string hash_order = "interleaved";                // --hash-order interleaved|polar-first
  int hash_bits = emu::HierarchyConfig{}.hash.polar_bits;  // --hash-bits: shadow keys' cells per angle
};

// Registers --hash-order and --hash-bits on `command`, writing into `args`.
void AddFaithfulOptions(CLI::App& command, FaithfulArgs& args);
// The largest --hash-bits: a shadow key holds the light index and both angles' cells.
int MaxHashBits();
// Sets the hierarchy configuration's fields the switches name.
void ApplyFaithful(const FaithfulArgs& args, emu::HierarchyConfig& hc);

}  // namespace rayspace::app
