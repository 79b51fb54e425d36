#include "rayspace/sim/program.h"

#include <spirv/unified1/spirv.hpp11>
#include <filesystem>
#include <set>
#include <spirv-tools/libspirv.h>
#include <spirv-tools/optimizer.hpp>

#include <fmt/format.h>

#include "rayspace/error.h"
#include "rayspace/sim/grammar.h"
#include "rayspace/sim/inventory.h"
#include "rayspace/sim/module_tools.h"

namespace rayspace::sim {
namespace {

using Op = spv::Op;

struct RawInst {
  std::uint16_t op;
  std::uint32_t type, result;
  std::vector<std::uint32_t> words;  // every word of the instruction
  std::uint32_t operand_start;       // index in words after the result type and id
};

spv_result_t Collect(void* user, const spv_parsed_instruction_t* in) {
  auto& out = *static_cast<std::vector<RawInst>*>(user);
  RawInst r{in->opcode, in->type_id, in->result_id, std::vector<std::uint32_t>(in->words, in->words + in->num_words), 1};
  r.operand_start = 1 + (in->type_id ? 1u : 0u) + (in->result_id ? 1u : 0u);
  out.push_back(std::move(r));
  return SPV_SUCCESS;
}

// The SpecIds of boolean specialization constants: spirv-opt takes their values as "true" or
// "false" and leaves a boolean given as a number at its default, silently.
std::set<std::uint32_t> BooleanSpecIds(std::span<const std::uint32_t> spirv) {
  std::map<std::uint32_t, std::uint32_t> spec_id;  // result id -> SpecId
  std::set<std::uint32_t> booleans;                // result ids
  for (std::size_t at = 5; at < spirv.size();) {
    const std::uint32_t count = spirv[at] >> 16, op = spirv[at] & 0xffffu;
    if (count == 0 || at + count > spirv.size()) break;  // spirv-val has accepted the module; defensive only
    if (op == static_cast<std::uint32_t>(Op::OpDecorate) && count >= 4 && spirv[at + 2] == static_cast<std::uint32_t>(spv::Decoration::SpecId))
      spec_id[spirv[at + 1]] = spirv[at + 3];
    if ((op == static_cast<std::uint32_t>(Op::OpSpecConstantTrue) || op == static_cast<std::uint32_t>(Op::OpSpecConstantFalse)) && count >= 3)
      booleans.insert(spirv[at + 2]);
    at += count;
  }
  std::set<std::uint32_t> ids;
  for (const auto& [id, sid] : spec_id)
    if (booleans.count(id)) ids.insert(sid);
  return ids;
}

std::vector<std::uint32_t> Optimized(std::span<const std::uint32_t> spirv, const Specialization& spec, const std::string& name) {
  spvtools::Optimizer opt(SPV_ENV_VULKAN_1_2);
  std::string first;
  opt.SetMessageConsumer([&first](spv_message_level_t level, const char*, const spv_position_t&, const char* m) {
    if (level <= SPV_MSG_ERROR && first.empty()) first = OneLine(m);
  });
  std::unordered_map<std::uint32_t, std::string> values(spec.begin(), spec.end());
  // A boolean's value as Vulkan reads it (a VkBool32: nonzero is true), in the words spirv-opt takes.
  for (const std::uint32_t id : BooleanSpecIds(spirv))
    if (const auto v = values.find(id); v != values.end()) v->second = v->second == "0" || v->second == "false" ? "false" : "true";
  opt.RegisterPass(spvtools::CreateSetSpecConstantDefaultValuePass(values))
      .RegisterPass(spvtools::CreateFreezeSpecConstantValuePass())
      .RegisterPass(spvtools::CreateFoldSpecConstantOpAndCompositePass())
      .RegisterPass(spvtools::CreateMergeReturnPass())
      .RegisterPass(spvtools::CreateInlineExhaustivePass())
      .RegisterPass(spvtools::CreateEliminateDeadFunctionsPass());
  std::vector<std::uint32_t> out;
  if (!opt.Run(spirv.data(), spirv.size(), &out)) ThrowInput("{}: spirv-opt could not specialise and inline it: {}", name, first);
  return out;
}

class Builder {
 public:
  Builder(Program& p, std::uint32_t bound) : p_(p) {
    p_.types.resize(bound);
    p_.reg.assign(bound, ~0u);
    p_.value_type.assign(bound, 0);
    p_.segment_of_label.assign(bound, ~0u);
  }

  void Decorations(const std::vector<RawInst>& insts) {
    for (const RawInst& r : insts) {
      const auto& w = r.words;
      if (r.op == static_cast<std::uint16_t>(Op::OpDecorate) && w.size() >= 3) {
        const auto d = static_cast<spv::Decoration>(w[2]);
        if (d == spv::Decoration::ArrayStride || d == spv::Decoration::MatrixStride) stride_[w[1]] = w[3];
        if (d == spv::Decoration::Binding) binding_[w[1]] = w[3];
        if (d == spv::Decoration::BuiltIn) builtin_[w[1]] = w[3];
        if (d == spv::Decoration::NoContraction) precise_.insert(w[1]);
      } else if (r.op == static_cast<std::uint16_t>(Op::OpMemberDecorate) && w.size() >= 4) {
        const auto d = static_cast<spv::Decoration>(w[3]);
        if (d == spv::Decoration::Offset) member_offset_[{w[1], w[2]}] = w[4];
        if (d == spv::Decoration::MatrixStride) member_stride_[{w[1], w[2]}] = w[4];
      }
    }
  }

  void Global(const RawInst& r) {
    const auto& w = r.words;
    Type t;
    switch (static_cast<Op>(r.op)) {
      case Op::OpTypeVoid: t.kind = TypeKind::kVoid; break;
      case Op::OpTypeBool: t.kind = TypeKind::kBool; t.words = 1; break;
      case Op::OpTypeInt: t.kind = TypeKind::kInt; t.width = w[2]; t.is_signed = w[3] != 0; t.words = w[2] == 64 ? 2 : 1; break;
      case Op::OpTypeFloat: t.kind = TypeKind::kFloat; t.width = w[2]; t.words = w[2] == 64 ? 2 : 1; break;
      case Op::OpTypeVector:
      case Op::OpTypeMatrix:
        t.kind = r.op == static_cast<std::uint16_t>(Op::OpTypeVector) ? TypeKind::kVector : TypeKind::kMatrix;
        t.element = w[2];
        t.count = w[3];
        t.words = t.count * p_.T(t.element).words;
        break;
      case Op::OpTypeArray:
        t.kind = TypeKind::kArray;
        t.element = w[2];
        t.count = p_.constants.at(p_.reg.at(w[3]));
        t.words = t.count * p_.T(t.element).words;
        break;
      case Op::OpTypeRuntimeArray: t.kind = TypeKind::kRuntimeArray; t.element = w[2]; break;
      case Op::OpTypeStruct:
        t.kind = TypeKind::kStruct;
        for (std::size_t i = 2; i < w.size(); ++i) {
          t.members.push_back(w[i]);
          t.words += p_.T(w[i]).words;
          const auto off = member_offset_.find({w[1], static_cast<std::uint32_t>(i - 2)});
          t.offsets.push_back(off == member_offset_.end() ? 0 : off->second);
        }
        break;
      case Op::OpTypePointer: t.kind = TypeKind::kPointer; t.storage = w[2]; t.element = w[3]; t.words = 2; break;
      case Op::OpTypeFunction: t.kind = TypeKind::kFunction; break;
      default: Value(r); return;
    }
    if (const auto s = stride_.find(w[1]); s != stride_.end()) t.stride = s->second;
    p_.types[w[1]] = std::move(t);
  }

  // Matrix strides decorate struct members; the matrix type takes the first it meets.
  void MemberStrides() {
    for (const auto& [key, stride] : member_stride_) {
      const Type& s = p_.T(key.first);
      if (key.second < s.members.size()) p_.types[s.members[key.second]].stride = stride;
    }
  }

  // Constants and module-scope variables.
  void Value(const RawInst& r) {
    const auto& w = r.words;
    switch (static_cast<Op>(r.op)) {
      case Op::OpConstant:
      case Op::OpSpecConstant: {
        const std::uint32_t at = Allocate(r.type, r.result);
        for (std::size_t i = 3; i < w.size(); ++i) p_.constants[at + i - 3] = w[i];
        break;
      }
      case Op::OpConstantTrue:
      case Op::OpSpecConstantTrue: p_.constants[Allocate(r.type, r.result)] = 1; break;
      case Op::OpConstantFalse:
      case Op::OpSpecConstantFalse:
      case Op::OpConstantNull:
      case Op::OpUndef: Allocate(r.type, r.result); break;
      case Op::OpConstantComposite:
      case Op::OpSpecConstantComposite: {
        std::uint32_t at = Allocate(r.type, r.result);
        for (std::size_t i = 3; i < w.size(); ++i) {
          const std::uint32_t n = p_.T(p_.value_type.at(w[i])).words;
          std::copy_n(p_.constants.begin() + p_.reg.at(w[i]), n, p_.constants.begin() + at);
          at += n;
        }
        if (const auto b = builtin_.find(r.result); b != builtin_.end() && b->second == static_cast<std::uint32_t>(spv::BuiltIn::WorkgroupSize))
          for (int k = 0; k < 3; ++k) p_.local_size[k] = p_.constants[p_.reg[r.result] + k];
        break;
      }
      case Op::OpVariable: Variable(r); break;
      case Op::OpSpecConstantOp: SpecConstantOp(r); break;
      default: break;
    }
  }

  // What spirv-opt leaves unfolded (a float Select, say), on 32-bit scalars: the constant's words.
  void SpecConstantOp(const RawInst& r) {
    const auto& w = r.words;
    const auto op = static_cast<Op>(w[3]);
    const std::uint32_t at = Allocate(r.type, r.result), words = p_.T(r.type).words;
    const auto v = [&](std::size_t k) { return p_.constants.at(p_.reg.at(w[4 + k])); };
    if (op == Op::OpSelect) {
      std::copy_n(p_.constants.begin() + p_.reg.at(w[v(0) ? 5 : 6]), words, p_.constants.begin() + at);
      return;
    }
    if (words != 1) ThrowInput("{}: a specialization constant operation on a {}-word value", p_.name, words);
    std::uint32_t x = 0;
    switch (op) {
      case Op::OpIAdd: x = v(0) + v(1); break;
      case Op::OpISub: x = v(0) - v(1); break;
      case Op::OpIMul: x = v(0) * v(1); break;
      case Op::OpUDiv: x = v(1) ? v(0) / v(1) : 0; break;
      case Op::OpUMod: x = v(1) ? v(0) % v(1) : 0; break;
      case Op::OpBitwiseAnd: x = v(0) & v(1); break;
      case Op::OpBitwiseOr: x = v(0) | v(1); break;
      case Op::OpBitwiseXor: x = v(0) ^ v(1); break;
      case Op::OpShiftLeftLogical: x = v(1) < 32 ? v(0) << v(1) : 0; break;
      case Op::OpShiftRightLogical: x = v(1) < 32 ? v(0) >> v(1) : 0; break;
      case Op::OpIEqual:
      case Op::OpLogicalEqual: x = v(0) == v(1); break;
      case Op::OpINotEqual:
      case Op::OpLogicalNotEqual: x = v(0) != v(1); break;
      case Op::OpULessThan: x = v(0) < v(1); break;
      case Op::OpUGreaterThan: x = v(0) > v(1); break;
      case Op::OpULessThanEqual: x = v(0) <= v(1); break;
      case Op::OpUGreaterThanEqual: x = v(0) >= v(1); break;
      case Op::OpLogicalAnd: x = v(0) && v(1); break;
      case Op::OpLogicalOr: x = v(0) || v(1); break;
      case Op::OpLogicalNot: x = !v(0); break;
      case Op::OpNot: x = ~v(0); break;
      case Op::OpUConvert:
      case Op::OpSConvert: x = v(0); break;
      default: ThrowInput("{}: a specialization constant operation {} the simulator does not evaluate", p_.name, NameOf("Opcode", w[3]));
    }
    p_.constants[at] = x;
  }

  void Variable(const RawInst& r) {
    sim::Variable v;
    v.id = r.result;
    v.type = r.type;
    v.storage = r.words[3];
    if (r.words.size() > 4) v.initializer = r.words[4];
    if (const auto b = binding_.find(r.result); b != binding_.end()) v.binding = b->second;
    if (const auto b = builtin_.find(r.result); b != builtin_.end()) v.builtin = b->second;
    Allocate(r.type, r.result);
    p_.variables.push_back(v);
  }

  std::uint32_t Allocate(std::uint32_t type, std::uint32_t id) {
    p_.value_type[id] = type;
    p_.reg[id] = p_.reg_words;
    p_.reg_words += p_.T(type).words;
    p_.constants.resize(p_.reg_words, 0);
    return p_.reg[id];
  }


  void Function(const std::vector<RawInst>& insts, std::size_t begin, std::size_t end) {
    std::uint32_t line = 0, file = 0, order = 0;
    Segment seg;
    bool open = false;
    for (std::size_t i = begin; i < end; ++i) {
      const RawInst& r = insts[i];
      const auto op = static_cast<Op>(r.op);
      if (op == Op::OpLine) {
        file = r.words[1];
        line = r.words[2];
        continue;
      }
      if (op == Op::OpNoLine) line = file = 0;
      if (op == Op::OpNoLine || op == Op::OpFunctionParameter || op == Op::OpFunctionEnd) continue;
      if (op == Op::OpFunctionCall) ThrowInput("{}: a function call spirv-opt did not inline", p_.name);
      if (op == Op::OpLabel) {
        seg = Segment{r.result, static_cast<std::uint32_t>(p_.code.size()), 0, order++};
        p_.segment_of_label[r.result] = static_cast<std::uint32_t>(p_.segments.size());
        open = true;
        continue;
      }
      if (op == Op::OpVariable) {
        Variable(r);
        continue;
      }
      if (!open) continue;
      Inst in{r.op, static_cast<std::uint16_t>(r.words.size() - r.operand_start), r.type, r.result,
              static_cast<std::uint32_t>(p_.operands.size()), line, file};
      p_.operands.insert(p_.operands.end(), r.words.begin() + r.operand_start, r.words.end());
      if (r.result && r.type) Allocate(r.type, r.result);
      p_.code.push_back(in);
      const bool barrier = op == Op::OpControlBarrier;
      const bool terminator = op == Op::OpBranch || op == Op::OpBranchConditional || op == Op::OpSwitch || op == Op::OpReturn ||
                              op == Op::OpReturnValue || op == Op::OpUnreachable || op == Op::OpKill;
      if (barrier || terminator) {
        seg.end = static_cast<std::uint32_t>(p_.code.size());
        p_.segments.push_back(seg);
        seg = Segment{seg.label, seg.end, 0, order++};
        open = barrier;
      }
    }
  }

  // Program::contract: within one block, the adds and subtracts a device may fuse with a multiply.
  void Contractions() {
    p_.contract.assign(p_.code.size(), kNoContraction);
    std::map<std::uint32_t, std::uint32_t> muls;  // result id -> index, of the current block's contractible multiplies
    std::uint32_t label = 0;
    for (const Segment& seg : p_.segments) {
      if (seg.label != label) muls.clear();
      label = seg.label;
      for (std::uint32_t i = seg.first; i < seg.end; ++i) {
        const Inst& in = p_.code[i];
        const auto op = static_cast<Op>(in.op);
        if (op == Op::OpFMul && !precise_.count(in.result)) muls[in.result] = i;
        if ((op != Op::OpFAdd && op != Op::OpFSub) || precise_.count(in.result)) continue;
        const auto ops = p_.Ops(in);
        if (const auto m = muls.find(ops[0]); m != muls.end()) p_.contract[i] = m->second;
        else if (const auto m1 = muls.find(ops[1]); m1 != muls.end()) p_.contract[i] = m1->second | kContractSecond;
      }
    }
  }

 private:
  Program& p_;
  std::map<std::uint32_t, std::uint32_t> stride_, binding_, builtin_;
  std::set<std::uint32_t> precise_;  // NoContraction
  std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> member_offset_, member_stride_;
};

}  // namespace

Program Prepare(std::span<const std::uint32_t> spirv, const Specialization& spec, const std::string& name) {
  if (const std::string e = ValidationError(spirv); !e.empty()) ThrowInput("{}: not valid SPIR-V for Vulkan 1.2 (spirv-val): {}", name, e);
  for (const Feature& f : OutsideScope(InventoryOf(spirv, name)))
    ThrowInput("{}: uses {} {}, which the simulator does not execute (docs/simulator.md, \"The scope\")", name, f.kind, f.name);
  const std::vector<std::uint32_t> words = Optimized(spirv, spec, name);
  std::vector<RawInst> insts;
  spv_context ctx = spvContextCreate(SPV_ENV_VULKAN_1_2);
  const spv_result_t rc = spvBinaryParse(ctx, &insts, words.data(), words.size(), nullptr, Collect, nullptr);
  spvContextDestroy(ctx);
  if (rc != SPV_SUCCESS || words.size() < 5) ThrowInput("{}: the prepared module does not parse", name);

  Program p;
  p.name = name;
  Builder b(p, words[3]);
  b.Decorations(insts);
  std::uint32_t entry = 0;
  std::size_t fn_begin = 0, fn_end = 0;
  for (std::size_t i = 0; i < insts.size(); ++i) {
    const RawInst& r = insts[i];
    const auto op = static_cast<Op>(r.op);
    if (op == Op::OpEntryPoint) entry = r.words[2];
    if (op == Op::OpExtInstImport) p.glsl_set = r.result;
    if (op == Op::OpString) p.strings[r.result] = OneLine(reinterpret_cast<const char*>(r.words.data() + 2));
    if (op == Op::OpName && r.words.size() > 2) p.names[r.words[1]] = OneLine(reinterpret_cast<const char*>(r.words.data() + 2));
    if (op == Op::OpExecutionMode && r.words.size() >= 6 && r.words[2] == static_cast<std::uint32_t>(spv::ExecutionMode::LocalSize))
      for (int k = 0; k < 3; ++k) p.local_size[k] = r.words[3 + k];
    if (op == Op::OpFunction) {
      if (r.result == entry) fn_begin = i;
      continue;
    }
    if (op == Op::OpFunctionEnd && fn_begin && !fn_end) fn_end = i + 1;
    if (!fn_begin && r.op != static_cast<std::uint16_t>(Op::OpLabel)) b.Global(r);
  }
  b.MemberStrides();
  if (!fn_begin) ThrowInput("{}: no entry point function", name);
  b.Function(insts, fn_begin, fn_end);
  b.Contractions();
  // The workgroup limits a device reports (lavapipe's, which are Vulkan's usual ones): a pipeline
  // beyond them is not created, so the simulator refuses it too.
  const std::uint32_t* ls = p.local_size;
  constexpr std::uint32_t kMaxSize[3] = {1024, 1024, 64}, kMaxInvocations = 1024;
  const std::uint64_t invocations = std::uint64_t{ls[0]} * ls[1] * ls[2];
  if (ls[0] > kMaxSize[0] || ls[1] > kMaxSize[1] || ls[2] > kMaxSize[2] || invocations > kMaxInvocations || invocations == 0)
    ThrowInput("{}: a workgroup of {}x{}x{} invocations, beyond the device's maxComputeWorkGroupSize (1024, 1024, 64) and "
               "maxComputeWorkGroupInvocations (1024)",
               name, ls[0], ls[1], ls[2]);
  return p;
}

std::string Program::Where(const Inst& in) const {
  if (in.line) {
    const auto f = strings.find(in.file);
    if (f == strings.end()) return fmt::format("{} line {}", name, in.line);
    return fmt::format("{} {}:{}", name, std::filesystem::path(f->second).filename().string(), in.line);
  }
  return in.result ? fmt::format("{} main %{}", name, in.result) : name;
}

}  // namespace rayspace::sim
