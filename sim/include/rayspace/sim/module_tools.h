// SPIRV-Tools on a module: the validator (spirv-val) the simulator runs before executing anything, and
// the debug-information strip that shows glslc -g leaves the computing instructions as they were.
#pragma once
#include <cstdint>
#include <map>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace rayspace::sim {

// `text` on one line: control characters become spaces and runs of spaces one. SPIRV-Tools' messages
// put the offending instruction on a line of its own, and a module's strings (OpSource text, names)
// may hold any bytes; an error the user reads is one line.
std::string OneLine(std::string_view text);

// spirv-val's verdict for the Vulkan 1.2 environment (SPIR-V up to 1.5): "" when valid, else its
// first message, on one line.
std::string ValidationError(std::span<const std::uint32_t> spirv);

// The module without debug instructions (OpSource, OpString, OpName, OpLine, ...) and with its ids
// renumbered in order of first appearance (spirv-opt --strip-debug --compact-ids). Throws InputError
// naming `what` when SPIRV-Tools rejects it.
std::vector<std::uint32_t> WithoutDebugInfo(std::span<const std::uint32_t> spirv, const std::string& what);

// The module as a pipeline with these specialization constants (SpecId -> decimal text, "true" or
// "false" for a boolean) runs it: the constants frozen and folded, functions inlined, branches on
// them resolved and what they make dead removed (spirv-opt's set-spec-const-default-value,
// freeze-spec-const, fold-spec-const-op-composite, inline, ccp, dead-branch-elim, aggressive-dce).
// Throws InputError naming `what` when SPIRV-Tools rejects it.
std::vector<std::uint32_t> Specialized(std::span<const std::uint32_t> spirv, const std::map<std::uint32_t, std::string>& spec,
                                       const std::string& what);

// The module with these specialization constants frozen, the branches they decide removed and the
// functions no longer called dropped (spirv-opt's set-spec-const-default-value, freeze-spec-const,
// fold-spec-const-op-composite, eliminate-dead-branches, eliminate-dead-functions): no instruction
// that computes is changed, inlined or folded. What the Vulkan runtime gives a device. Throws
// InputError naming `what` when SPIRV-Tools rejects it.
std::vector<std::uint32_t> WithBranchesDecided(std::span<const std::uint32_t> spirv, const std::map<std::uint32_t, std::string>& spec,
                                               const std::string& what);

// The instructions a conformant Vulkan device may round loosely that a module still holds: OpFDiv,
// and GLSL.std.450 Sqrt and InverseSqrt, of any float width. Each as "FILE:LINE OpFDiv (64-bit)"
// (the OpLine before it; "?" without debug information).
std::vector<std::string> LooselyRounded(std::span<const std::uint32_t> spirv);

}  // namespace rayspace::sim
