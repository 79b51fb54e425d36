// A kernel's SPIR-V prepared for execution: validated, checked against the scope, specialised and
// inlined by spirv-opt (recipes that leave the arithmetic as written), then decoded once into tables
// the executor reads: types, the register file's layout, constants, variables and basic blocks.
#pragma once
#include <cstdint>
#include <map>
#include <span>
#include <string>
#include <vector>

namespace rayspace::sim {

enum class TypeKind : std::uint8_t { kNone, kVoid, kBool, kInt, kFloat, kVector, kMatrix, kArray, kRuntimeArray, kStruct, kPointer, kFunction };

struct Type {
  TypeKind kind = TypeKind::kNone;
  std::uint32_t width = 0;      // bits of an int or float
  bool is_signed = false;
  std::uint32_t count = 0;      // vector components, matrix columns, array length
  std::uint32_t element = 0;    // component, column, element or pointee type id
  std::uint32_t storage = 0;    // pointer: spv::StorageClass
  std::vector<std::uint32_t> members;   // struct member type ids
  std::vector<std::uint32_t> offsets;   // struct member byte offsets (Offset decorations), explicit layout
  std::uint32_t stride = 0;     // ArrayStride / MatrixStride, explicit layout
  std::uint32_t words = 0;      // 32-bit words of a value in the register file
};

// One instruction: operand words (after the result type and result id) in Program::operands.
struct Inst {
  std::uint16_t op = 0;
  std::uint16_t count = 0;
  std::uint32_t type = 0, result = 0;
  std::uint32_t first = 0;
  std::uint32_t line = 0;  // the GLSL line of the last OpLine before it (0: none)
  std::uint32_t file = 0;  // that OpLine's file (an OpString id)
};

// A basic block cut at barriers: a segment ends with its terminator or an OpControlBarrier, after
// which the next segment of the same block goes on (the executor waits there for the workgroup).
struct Segment {
  std::uint32_t label = 0;       // the block's label id
  std::uint32_t first = 0, end = 0;  // instructions [first, end)
  std::uint32_t order = 0;       // position in the function: the executor steps the lowest first
};

struct Variable {
  std::uint32_t id = 0, type = 0;  // type: the pointer type
  std::uint32_t storage = 0;
  std::uint32_t binding = ~0u;     // StorageBuffer
  std::uint32_t builtin = ~0u;     // Input
  std::uint32_t initializer = 0;
};

constexpr std::uint32_t kNoContraction = ~0u, kContractSecond = 1u << 31;

struct Program {
  std::string name;
  std::vector<Type> types;                   // by id
  std::vector<std::uint32_t> reg;            // register offset by id (~0u: none)
  std::vector<std::uint32_t> value_type;     // the type of each value (constant, variable, result) by id
  std::uint32_t reg_words = 0;
  std::vector<std::uint32_t> constants;      // the register file's initial image: constants filled in
  std::vector<Inst> code;
  std::vector<std::uint32_t> operands;
  std::vector<Segment> segments;             // in function order
  std::vector<std::uint32_t> segment_of_label;  // by label id: its first segment (~0u: not a label); a branch looks it up per lane
  std::vector<Variable> variables;           // module-scope and the entry function's
  std::uint32_t local_size[3] = {1, 1, 1};
  std::uint32_t glsl_set = 0;                // the GLSL.std.450 import's id
  std::map<std::uint32_t, std::string> strings;  // OpString by id: the source files OpLine names
  std::map<std::uint32_t, std::string> names;  // OpName: the GLSL names of variables (for reports)
  // By instruction: for an OpFAdd or OpFSub a device may fuse with an OpFMul operand computed in the
  // same block (neither decorated NoContraction), that multiply's index, with kContractSecond set
  // when it is the second operand; kNoContraction otherwise.
  std::vector<std::uint32_t> contract;

  const Type& T(std::uint32_t id) const { return types.at(id); }
  // Where an instruction is, for reports: "trim workgroup.glsl:44" from debug info, else the
  // kernel, the entry function and the result id: "trim main %57".
  std::string Where(const Inst& in) const;
  std::span<const std::uint32_t> Ops(const Inst& i) const { return {operands.data() + i.first, i.count}; }
};

// Specialization constants by SpecId, as decimal text (spirv-opt takes them so).
using Specialization = std::map<std::uint32_t, std::string>;

// Throws InputError naming `name` when the module is not valid SPIR-V, uses a feature outside the
// scope (naming it), or spirv-opt cannot prepare it.
Program Prepare(std::span<const std::uint32_t> spirv, const Specialization& spec, const std::string& name);

}  // namespace rayspace::sim
