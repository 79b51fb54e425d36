// What a SPIR-V module uses, by kind: its opcodes, capabilities, storage classes, built-ins,
// execution modes, decorations, group operations and GLSL.std.450 instructions, named as the grammar
// names them. The simulator's scope (scope.h) is checked against it: a kernel that uses anything
// outside the scope is refused by name before it runs.
#pragma once
#include <cstdint>
#include <map>
#include <set>
#include <span>
#include <string>
#include <vector>

namespace rayspace::sim {

// kind ("Opcode", "Capability", "StorageClass", "BuiltIn", "ExecutionMode", "Decoration",
// "GroupOperation", "GLSL.std.450") -> names.
using Inventory = std::map<std::string, std::set<std::string>>;

// Throws InputError naming `what` when the words are not a SPIR-V module SPIRV-Tools can parse.
Inventory InventoryOf(std::span<const std::uint32_t> spirv, const std::string& what);

struct Feature {
  std::string kind, name;
  bool operator<(const Feature& o) const { return kind != o.kind ? kind < o.kind : name < o.name; }
};
// The features of `used` the simulator's scope lacks, in kind and name order.
std::vector<Feature> OutsideScope(const Inventory& used);

}  // namespace rayspace::sim
