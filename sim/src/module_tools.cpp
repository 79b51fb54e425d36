#include "rayspace/sim/module_tools.h"

#include <spirv-tools/libspirv.hpp>
#include <spirv-tools/optimizer.hpp>
#include <spirv/unified1/GLSL.std.450.h>
#include <spirv/unified1/spirv.hpp11>

#include <functional>
#include <unordered_map>

#include <fmt/format.h>

#include "rayspace/error.h"

namespace rayspace::sim {

std::string OneLine(std::string_view text) {
  std::string out;
  for (const char c : text) {
    const bool space = static_cast<unsigned char>(c) < 0x20 || c == 0x7f || c == ' ';
    if (!space) out += c;
    else if (!out.empty() && out.back() != ' ') out += ' ';
  }
  while (!out.empty() && out.back() == ' ') out.pop_back();
  return out;
}

std::string ValidationError(std::span<const std::uint32_t> spirv) {
  spvtools::SpirvTools tools(SPV_ENV_VULKAN_1_2);
  std::string first;
  tools.SetMessageConsumer([&first](spv_message_level_t, const char*, const spv_position_t&, const char* message) {
    if (first.empty()) first = OneLine(message);
  });
  if (tools.Validate(spirv.data(), spirv.size())) return "";
  return first.empty() ? "invalid (no message)" : first;
}

namespace {

// spirv-opt's passes that `add` registers run on the module; a failure throws InputError naming
// `what` and `failed` with SPIRV-Tools' first message (of any level when `any_message`, else its
// first error).
std::vector<std::uint32_t> Optimize(std::span<const std::uint32_t> spirv, const std::string& what, std::string_view failed,
                                    const std::function<void(spvtools::Optimizer&)>& add, bool any_message = false) {
  spvtools::Optimizer opt(SPV_ENV_VULKAN_1_2);
  std::string first;
  opt.SetMessageConsumer([&first, any_message](spv_message_level_t level, const char*, const spv_position_t&, const char* message) {
    if ((any_message || level <= SPV_MSG_ERROR) && first.empty()) first = OneLine(message);
  });
  add(opt);
  std::vector<std::uint32_t> out;
  if (!opt.Run(spirv.data(), spirv.size(), &out)) ThrowInput("{}: {}: {}", what, failed, first);
  return out;
}

// The pipeline's specialization constants set and frozen, and the operations on them folded.
void Freeze(spvtools::Optimizer& opt, const std::map<std::uint32_t, std::string>& spec) {
  const std::unordered_map<std::uint32_t, std::string> values(spec.begin(), spec.end());
  opt.RegisterPass(spvtools::CreateSetSpecConstantDefaultValuePass(values))
      .RegisterPass(spvtools::CreateFreezeSpecConstantValuePass())
      .RegisterPass(spvtools::CreateFoldSpecConstantOpAndCompositePass());
}

}  // namespace

std::vector<std::uint32_t> WithoutDebugInfo(std::span<const std::uint32_t> spirv, const std::string& what) {
  return Optimize(spirv, what, "spirv-opt --strip-debug failed", [](spvtools::Optimizer& opt) {
    opt.RegisterPass(spvtools::CreateStripDebugInfoPass()).RegisterPass(spvtools::CreateCompactIdsPass());
  }, /*any_message=*/true);
}

std::vector<std::uint32_t> Specialized(std::span<const std::uint32_t> spirv, const std::map<std::uint32_t, std::string>& spec,
                                       const std::string& what) {
  return Optimize(spirv, what, "spirv-opt could not specialise it", [&spec](spvtools::Optimizer& opt) {
    Freeze(opt, spec);
    opt.RegisterPass(spvtools::CreateMergeReturnPass())
        .RegisterPass(spvtools::CreateInlineExhaustivePass())
        .RegisterPass(spvtools::CreateLocalSingleStoreElimPass())
        .RegisterPass(spvtools::CreateCCPPass())
        .RegisterPass(spvtools::CreateDeadBranchElimPass())
        .RegisterPass(spvtools::CreateAggressiveDCEPass())
        .RegisterPass(spvtools::CreateEliminateDeadFunctionsPass());
  });
}

std::vector<std::uint32_t> WithBranchesDecided(std::span<const std::uint32_t> spirv, const std::map<std::uint32_t, std::string>& spec,
                                               const std::string& what) {
  return Optimize(spirv, what, "spirv-opt could not freeze its specialization constants", [&spec](spvtools::Optimizer& opt) {
    Freeze(opt, spec);
    opt.RegisterPass(spvtools::CreateDeadBranchElimPass()).RegisterPass(spvtools::CreateEliminateDeadFunctionsPass());
  });
}

std::vector<std::string> LooselyRounded(std::span<const std::uint32_t> spirv) {
  std::vector<std::string> found;
  if (spirv.size() < 5 || spirv[0] != spv::MagicNumber) return found;
  std::unordered_map<std::uint32_t, std::string> strings;
  std::unordered_map<std::uint32_t, std::uint32_t> float_width;  // a float type or vector -> its width
  std::uint32_t glsl = 0;
  std::string where = "?";
  const auto word_string = [&](std::size_t at, std::size_t end) {
    std::string text;
    for (std::size_t i = at; i < end; ++i)
      for (int b = 0; b < 4; ++b)
        if (const char c = static_cast<char>((spirv[i] >> (8 * b)) & 0xffu); c != 0) text += c;
        else return text;
    return text;
  };
  const auto width = [&](std::uint32_t type) {
    const auto it = float_width.find(type);
    return it == float_width.end() ? 0u : it->second;
  };
  for (std::size_t at = 5; at < spirv.size();) {
    const std::uint32_t words = spirv[at] >> 16;
    const auto op = static_cast<spv::Op>(spirv[at] & 0xffffu);
    if (words == 0 || at + words > spirv.size()) break;
    const std::uint32_t* w = &spirv[at];
    if (op == spv::Op::OpString && words >= 3) {
      std::string file = word_string(at + 2, at + words);
      strings[w[1]] = file.substr(file.find_last_of('/') + 1);
    } else if (op == spv::Op::OpExtInstImport && words >= 3 && word_string(at + 2, at + words) == "GLSL.std.450") {
      glsl = w[1];
    } else if (op == spv::Op::OpTypeFloat && words >= 3) {
      float_width[w[1]] = w[2];
    } else if (op == spv::Op::OpTypeVector && words >= 4 && width(w[2]) != 0) {
      float_width[w[1]] = width(w[2]);
    } else if (op == spv::Op::OpLine && words >= 4) {
      where = fmt::format("{}:{}", strings.count(w[1]) ? strings[w[1]] : "?", w[2]);
    } else if (op == spv::Op::OpFDiv && words >= 5) {
      found.push_back(fmt::format("{} OpFDiv ({}-bit)", where, width(w[1])));
    } else if (op == spv::Op::OpExtInst && words >= 5 && w[3] == glsl && (w[4] == GLSLstd450Sqrt || w[4] == GLSLstd450InverseSqrt)) {
      found.push_back(fmt::format("{} {} ({}-bit)", where, w[4] == GLSLstd450Sqrt ? "Sqrt" : "InverseSqrt", width(w[1])));
    }
    at += words;
  }
  return found;
}

}  // namespace rayspace::sim
