// The simulator's scope: every SPIR-V feature it executes, by the grammar's names (sim_inventory_test
// checks each name against the grammar, and the built-in kernels against the list). A module using
// anything else is refused by name. Debug instructions (OpLine, OpSource, OpName, ...) carry no
// computation and are read for the reports only.
#pragma once
#include <string_view>
#include <utility>

namespace rayspace::sim {

struct ScopeEntry {
  std::string_view kind, name;
};

inline constexpr ScopeEntry kScope[] = {
    // Module structure and debug information.
    {"Opcode", "OpCapability"}, {"Opcode", "OpExtension"}, {"Opcode", "OpExtInstImport"}, {"Opcode", "OpMemoryModel"},
    {"Opcode", "OpEntryPoint"}, {"Opcode", "OpExecutionMode"}, {"Opcode", "OpExecutionModeId"}, {"Opcode", "OpSource"},
    {"Opcode", "OpSourceExtension"}, {"Opcode", "OpSourceContinued"}, {"Opcode", "OpString"}, {"Opcode", "OpName"},
    {"Opcode", "OpMemberName"}, {"Opcode", "OpLine"}, {"Opcode", "OpNoLine"}, {"Opcode", "OpModuleProcessed"},
    {"Opcode", "OpDecorate"}, {"Opcode", "OpMemberDecorate"}, {"Opcode", "OpDecorateId"},
    // Types and constants.
    {"Opcode", "OpTypeVoid"}, {"Opcode", "OpTypeBool"}, {"Opcode", "OpTypeInt"}, {"Opcode", "OpTypeFloat"},
    {"Opcode", "OpTypeVector"}, {"Opcode", "OpTypeMatrix"}, {"Opcode", "OpTypeArray"}, {"Opcode", "OpTypeRuntimeArray"}, {"Opcode", "OpTypeStruct"},
    {"Opcode", "OpTypePointer"}, {"Opcode", "OpTypeFunction"}, {"Opcode", "OpConstantTrue"}, {"Opcode", "OpConstantFalse"},
    {"Opcode", "OpConstant"}, {"Opcode", "OpConstantComposite"}, {"Opcode", "OpConstantNull"}, {"Opcode", "OpSpecConstantTrue"},
    {"Opcode", "OpSpecConstantFalse"}, {"Opcode", "OpSpecConstant"}, {"Opcode", "OpSpecConstantComposite"},
    {"Opcode", "OpSpecConstantOp"}, {"Opcode", "OpUndef"},
    // Memory and functions.
    {"Opcode", "OpVariable"}, {"Opcode", "OpLoad"}, {"Opcode", "OpStore"}, {"Opcode", "OpAccessChain"},
    {"Opcode", "OpInBoundsAccessChain"}, {"Opcode", "OpArrayLength"}, {"Opcode", "OpCopyLogical"}, {"Opcode", "OpCopyObject"},
    {"Opcode", "OpFunction"}, {"Opcode", "OpFunctionParameter"}, {"Opcode", "OpFunctionEnd"}, {"Opcode", "OpFunctionCall"},
    // Composites.
    {"Opcode", "OpCompositeConstruct"}, {"Opcode", "OpCompositeExtract"}, {"Opcode", "OpCompositeInsert"},
    {"Opcode", "OpVectorShuffle"}, {"Opcode", "OpVectorExtractDynamic"}, {"Opcode", "OpVectorInsertDynamic"},
    // Arithmetic, logic, comparison and conversion.
    {"Opcode", "OpSNegate"}, {"Opcode", "OpFNegate"}, {"Opcode", "OpIAdd"}, {"Opcode", "OpFAdd"}, {"Opcode", "OpISub"},
    {"Opcode", "OpFSub"}, {"Opcode", "OpIMul"}, {"Opcode", "OpFMul"}, {"Opcode", "OpUDiv"}, {"Opcode", "OpSDiv"},
    {"Opcode", "OpFDiv"}, {"Opcode", "OpUMod"}, {"Opcode", "OpSRem"}, {"Opcode", "OpSMod"}, {"Opcode", "OpVectorTimesScalar"}, {"Opcode", "OpDot"},
    {"Opcode", "OpShiftRightLogical"}, {"Opcode", "OpShiftRightArithmetic"}, {"Opcode", "OpShiftLeftLogical"},
    {"Opcode", "OpBitwiseOr"}, {"Opcode", "OpBitwiseXor"}, {"Opcode", "OpBitwiseAnd"}, {"Opcode", "OpNot"},
    {"Opcode", "OpBitCount"}, {"Opcode", "OpBitFieldUExtract"}, {"Opcode", "OpBitFieldInsert"},
    {"Opcode", "OpAny"}, {"Opcode", "OpAll"}, {"Opcode", "OpIsNan"}, {"Opcode", "OpIsInf"},
    {"Opcode", "OpLogicalEqual"}, {"Opcode", "OpLogicalNotEqual"}, {"Opcode", "OpLogicalOr"}, {"Opcode", "OpLogicalAnd"},
    {"Opcode", "OpLogicalNot"}, {"Opcode", "OpSelect"}, {"Opcode", "OpIEqual"}, {"Opcode", "OpINotEqual"},
    {"Opcode", "OpUGreaterThan"}, {"Opcode", "OpSGreaterThan"}, {"Opcode", "OpUGreaterThanEqual"},
    {"Opcode", "OpSGreaterThanEqual"}, {"Opcode", "OpULessThan"}, {"Opcode", "OpSLessThan"}, {"Opcode", "OpULessThanEqual"},
    {"Opcode", "OpSLessThanEqual"}, {"Opcode", "OpFOrdEqual"}, {"Opcode", "OpFUnordEqual"}, {"Opcode", "OpFOrdNotEqual"},
    {"Opcode", "OpFUnordNotEqual"}, {"Opcode", "OpFOrdLessThan"}, {"Opcode", "OpFUnordLessThan"},
    {"Opcode", "OpFOrdGreaterThan"}, {"Opcode", "OpFUnordGreaterThan"}, {"Opcode", "OpFOrdLessThanEqual"},
    {"Opcode", "OpFUnordLessThanEqual"}, {"Opcode", "OpFOrdGreaterThanEqual"}, {"Opcode", "OpFUnordGreaterThanEqual"},
    {"Opcode", "OpConvertFToU"}, {"Opcode", "OpConvertFToS"}, {"Opcode", "OpConvertSToF"}, {"Opcode", "OpConvertUToF"},
    {"Opcode", "OpUConvert"}, {"Opcode", "OpSConvert"}, {"Opcode", "OpFConvert"}, {"Opcode", "OpBitcast"},
    {"Opcode", "OpExtInst"},
    // Control flow.
    {"Opcode", "OpPhi"}, {"Opcode", "OpLoopMerge"}, {"Opcode", "OpSelectionMerge"}, {"Opcode", "OpLabel"},
    {"Opcode", "OpBranch"}, {"Opcode", "OpBranchConditional"}, {"Opcode", "OpSwitch"}, {"Opcode", "OpReturn"},
    {"Opcode", "OpReturnValue"}, {"Opcode", "OpUnreachable"}, {"Opcode", "OpKill"},
    // Synchronisation, atomics and subgroups.
    {"Opcode", "OpControlBarrier"}, {"Opcode", "OpMemoryBarrier"}, {"Opcode", "OpAtomicLoad"}, {"Opcode", "OpAtomicStore"},
    {"Opcode", "OpAtomicExchange"}, {"Opcode", "OpAtomicCompareExchange"}, {"Opcode", "OpAtomicIAdd"},
    {"Opcode", "OpAtomicISub"}, {"Opcode", "OpAtomicUMin"}, {"Opcode", "OpAtomicUMax"}, {"Opcode", "OpAtomicSMin"},
    {"Opcode", "OpAtomicSMax"}, {"Opcode", "OpAtomicAnd"}, {"Opcode", "OpAtomicOr"}, {"Opcode", "OpAtomicXor"},
    {"Opcode", "OpGroupNonUniformElect"}, {"Opcode", "OpGroupNonUniformAll"}, {"Opcode", "OpGroupNonUniformAny"},
    {"Opcode", "OpGroupNonUniformBroadcast"}, {"Opcode", "OpGroupNonUniformBroadcastFirst"},
    {"Opcode", "OpGroupNonUniformBallot"}, {"Opcode", "OpGroupNonUniformBallotBitCount"},
    {"Opcode", "OpGroupNonUniformBallotFindLSB"}, {"Opcode", "OpGroupNonUniformBallotFindMSB"},
    {"Opcode", "OpGroupNonUniformShuffle"}, {"Opcode", "OpGroupNonUniformIAdd"}, {"Opcode", "OpGroupNonUniformUMin"},
    {"Opcode", "OpGroupNonUniformUMax"}, {"Opcode", "OpGroupNonUniformFMin"}, {"Opcode", "OpGroupNonUniformFMax"},
    // Capabilities, storage classes, built-ins, execution modes, decorations, group operations.
    {"Capability", "Shader"}, {"Capability", "Int64"}, {"Capability", "Int64Atomics"}, {"Capability", "Float64"},
    {"Capability", "GroupNonUniform"}, {"Capability", "GroupNonUniformArithmetic"}, {"Capability", "GroupNonUniformBallot"},
    {"Capability", "GroupNonUniformShuffle"}, {"Capability", "GroupNonUniformVote"}, {"Capability", "SignedZeroInfNanPreserve"},
    {"StorageClass", "StorageBuffer"}, {"StorageClass", "Uniform"}, {"StorageClass", "Workgroup"},
    {"StorageClass", "PushConstant"}, {"StorageClass", "Input"}, {"StorageClass", "Private"}, {"StorageClass", "Function"},
    {"BuiltIn", "SubgroupSize"}, {"BuiltIn", "SubgroupId"}, {"BuiltIn", "SubgroupLocalInvocationId"},
    {"BuiltIn", "NumSubgroups"}, {"BuiltIn", "GlobalInvocationId"}, {"BuiltIn", "LocalInvocationId"},
    {"BuiltIn", "LocalInvocationIndex"}, {"BuiltIn", "WorkgroupId"}, {"BuiltIn", "NumWorkgroups"}, {"BuiltIn", "WorkgroupSize"},
    {"ExecutionMode", "LocalSize"}, {"ExecutionMode", "LocalSizeId"}, {"ExecutionMode", "SignedZeroInfNanPreserve"},
    {"Decoration", "SpecId"}, {"Decoration", "Block"}, {"Decoration", "BufferBlock"}, {"Decoration", "ArrayStride"}, {"Decoration", "MatrixStride"}, {"Decoration", "ColMajor"},
    {"Decoration", "Offset"}, {"Decoration", "BuiltIn"}, {"Decoration", "NonWritable"}, {"Decoration", "NonReadable"},
    {"Decoration", "DescriptorSet"}, {"Decoration", "Binding"}, {"Decoration", "NoContraction"}, {"Decoration", "Coherent"},
    {"Decoration", "Volatile"}, {"Decoration", "Restrict"}, {"Decoration", "Aliased"}, {"Decoration", "RelaxedPrecision"},
    {"GroupOperation", "Reduce"}, {"GroupOperation", "InclusiveScan"}, {"GroupOperation", "ExclusiveScan"},
    {"GLSL.std.450", "FAbs"}, {"GLSL.std.450", "SAbs"}, {"GLSL.std.450", "FSign"}, {"GLSL.std.450", "Floor"},
    {"GLSL.std.450", "Ceil"}, {"GLSL.std.450", "Trunc"}, {"GLSL.std.450", "RoundEven"},
    {"GLSL.std.450", "Fract"}, {"GLSL.std.450", "Sqrt"}, {"GLSL.std.450", "InverseSqrt"}, {"GLSL.std.450", "FMin"},
    {"GLSL.std.450", "UMin"}, {"GLSL.std.450", "SMin"}, {"GLSL.std.450", "FMax"}, {"GLSL.std.450", "UMax"},
    {"GLSL.std.450", "SMax"}, {"GLSL.std.450", "FClamp"}, {"GLSL.std.450", "UClamp"}, {"GLSL.std.450", "SClamp"},
    {"GLSL.std.450", "FMix"}, {"GLSL.std.450", "Step"}, {"GLSL.std.450", "FindILsb"}, {"GLSL.std.450", "FindUMsb"},
    {"GLSL.std.450", "FindSMsb"}, {"GLSL.std.450", "Normalize"}, {"GLSL.std.450", "Length"}, {"GLSL.std.450", "Cross"},
    {"GLSL.std.450", "Fma"},
};

}  // namespace rayspace::sim
