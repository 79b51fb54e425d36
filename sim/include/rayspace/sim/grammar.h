// Names of SPIR-V opcodes and operand values, read from the grammar JSON of spirv-headers (embedded
// at build time), so that nothing here restates the specification by hand.
#pragma once
#include <cstdint>
#include <string>
#include <string_view>

namespace rayspace::sim {

// The operand kinds the simulator names (the grammar's "kind" of an enumerated operand), and two of
// its own: "Opcode" and "GLSL.std.450" (an OpExtInst of that set).
inline constexpr std::string_view kOpcode = "Opcode";
inline constexpr std::string_view kGlslStd450 = "GLSL.std.450";

// "OpIAdd", "StorageBuffer", "FMin", ...; "<kind> <value>" for a value the grammar does not list.
std::string NameOf(std::string_view kind, std::uint32_t value);
// Whether the grammar lists `name` in `kind` (for the simulator's own tables: no misspelt entry).
bool GrammarLists(std::string_view kind, std::string_view name);

}  // namespace rayspace::sim
