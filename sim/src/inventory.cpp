#include "rayspace/sim/inventory.h"

#include <fmt/format.h>
#include <spirv-tools/libspirv.h>

#include "rayspace/error.h"
#include "rayspace/sim/grammar.h"
#include "rayspace/sim/scope.h"

namespace rayspace::sim {
namespace {

// The enumerated operand kinds the inventory records, as SPIRV-Tools types them.
const char* KindOf(spv_operand_type_t t) {
  switch (t) {
    case SPV_OPERAND_TYPE_CAPABILITY: return "Capability";
    case SPV_OPERAND_TYPE_STORAGE_CLASS: return "StorageClass";
    case SPV_OPERAND_TYPE_BUILT_IN: return "BuiltIn";
    case SPV_OPERAND_TYPE_EXECUTION_MODE: return "ExecutionMode";
    case SPV_OPERAND_TYPE_DECORATION: return "Decoration";
    case SPV_OPERAND_TYPE_GROUP_OPERATION: return "GroupOperation";
    default: return nullptr;
  }
}

spv_result_t OnInstruction(void* user, const spv_parsed_instruction_t* in) {
  Inventory& inv = *static_cast<Inventory*>(user);
  inv[std::string(kOpcode)].insert(NameOf(kOpcode, in->opcode));
  for (std::uint16_t i = 0; i < in->num_operands; ++i) {
    const spv_parsed_operand_t& op = in->operands[i];
    if (const char* kind = KindOf(op.type)) inv[kind].insert(NameOf(kind, in->words[op.offset]));
    if (op.type == SPV_OPERAND_TYPE_EXTENSION_INSTRUCTION_NUMBER) {
      if (in->ext_inst_type == SPV_EXT_INST_TYPE_GLSL_STD_450)
        inv[std::string(kGlslStd450)].insert(NameOf(kGlslStd450, in->words[op.offset]));
      else
        inv["ExtInstSet"].insert(fmt::format("set {} instruction {}", static_cast<int>(in->ext_inst_type), in->words[op.offset]));
    }
  }
  return SPV_SUCCESS;
}

}  // namespace

Inventory InventoryOf(std::span<const std::uint32_t> spirv, const std::string& what) {
  Inventory inv;
  spv_context ctx = spvContextCreate(SPV_ENV_VULKAN_1_2);
  spv_diagnostic diag = nullptr;
  const spv_result_t r = spvBinaryParse(ctx, &inv, spirv.data(), spirv.size(), nullptr, OnInstruction, &diag);
  std::string message = diag && diag->error ? diag->error : "";
  spvDiagnosticDestroy(diag);
  spvContextDestroy(ctx);
  if (r != SPV_SUCCESS) ThrowInput("{}: not a SPIR-V module SPIRV-Tools can parse: {}", what, message.empty() ? "no detail" : message);
  return inv;
}

std::vector<Feature> OutsideScope(const Inventory& used) {
  std::vector<Feature> out;
  for (const auto& [kind, names] : used)
    for (const std::string& name : names) {
      bool known = false;
      for (const ScopeEntry& e : kScope) known |= e.kind == kind && e.name == name;
      if (!known) out.push_back({kind, name});
    }
  return out;
}

}  // namespace rayspace::sim
