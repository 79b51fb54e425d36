#include "rayspace/gpu/float_controls.h"

#include <spirv/unified1/spirv.hpp11>

namespace rayspace::vk {
namespace {

constexpr std::uint32_t Word(std::uint32_t count, spv::Op op) { return count << 16 | static_cast<std::uint32_t>(op); }
constexpr std::uint32_t kWidth = 32;

}  // namespace

std::string FloatControls::Describe() const {
  if (!denorm_preserve && !round_to_nearest) return "none";
  if (denorm_preserve && round_to_nearest) return "DenormPreserve, RoundingModeRTE";
  return denorm_preserve ? "DenormPreserve" : "RoundingModeRTE";
}

FloatControls DeclaredFloatControls(std::span<const std::uint32_t> spirv) {
  FloatControls f;
  if (spirv.size() < 5 || spirv[0] != spv::MagicNumber) return f;
  for (std::size_t at = 5; at < spirv.size();) {
    const std::uint32_t words = spirv[at] >> 16;
    if (words == 0 || at + words > spirv.size()) break;
    if ((spirv[at] & 0xffffu) == static_cast<std::uint32_t>(spv::Op::OpExecutionMode) && words == 4 && spirv[at + 3] == kWidth) {
      f.denorm_preserve |= spirv[at + 2] == static_cast<std::uint32_t>(spv::ExecutionMode::DenormPreserve);
      f.round_to_nearest |= spirv[at + 2] == static_cast<std::uint32_t>(spv::ExecutionMode::RoundingModeRTE);
    }
    at += words;
  }
  return f;
}

std::vector<std::uint32_t> WithFloatControls(std::span<const std::uint32_t> spirv, FloatControls want) {
  std::vector<std::uint32_t> in(spirv.begin(), spirv.end());
  if (spirv.size() < 5 || spirv[0] != spv::MagicNumber) return in;
  const FloatControls have = DeclaredFloatControls(spirv);
  want.denorm_preserve = want.denorm_preserve && !have.denorm_preserve;
  want.round_to_nearest = want.round_to_nearest && !have.round_to_nearest;
  if (!want.denorm_preserve && !want.round_to_nearest) return in;
  // Capabilities come first; execution modes follow the entry points. Both are inserted after the
  // last of their kind, in the layout SPIR-V prescribes.
  std::size_t after_capabilities = 5, after_modes = 0;
  std::vector<std::uint32_t> entries;
  for (std::size_t at = 5; at < spirv.size();) {
    const std::uint32_t words = spirv[at] >> 16;
    if (words == 0 || at + words > spirv.size()) return in;
    const auto op = static_cast<spv::Op>(spirv[at] & 0xffffu);
    if (op == spv::Op::OpCapability) after_capabilities = at + words;
    if (op == spv::Op::OpEntryPoint && words >= 3) entries.push_back(spirv[at + 2]);
    if (op == spv::Op::OpEntryPoint || op == spv::Op::OpExecutionMode || op == spv::Op::OpExecutionModeId) after_modes = at + words;
    at += words;
  }
  if (entries.empty()) return in;
  std::vector<std::uint32_t> capabilities, modes;
  const auto add = [&](spv::Capability c, spv::ExecutionMode m) {
    capabilities.insert(capabilities.end(), {Word(2, spv::Op::OpCapability), static_cast<std::uint32_t>(c)});
    for (const std::uint32_t e : entries)
      modes.insert(modes.end(), {Word(4, spv::Op::OpExecutionMode), e, static_cast<std::uint32_t>(m), kWidth});
  };
  if (want.denorm_preserve) add(spv::Capability::DenormPreserve, spv::ExecutionMode::DenormPreserve);
  if (want.round_to_nearest) add(spv::Capability::RoundingModeRTE, spv::ExecutionMode::RoundingModeRTE);
  std::vector<std::uint32_t> out;
  out.reserve(in.size() + capabilities.size() + modes.size());
  out.insert(out.end(), in.begin(), in.begin() + static_cast<std::ptrdiff_t>(after_capabilities));
  out.insert(out.end(), capabilities.begin(), capabilities.end());
  out.insert(out.end(), in.begin() + static_cast<std::ptrdiff_t>(after_capabilities), in.begin() + static_cast<std::ptrdiff_t>(after_modes));
  out.insert(out.end(), modes.begin(), modes.end());
  out.insert(out.end(), in.begin() + static_cast<std::ptrdiff_t>(after_modes), in.end());
  return out;
}

}  // namespace rayspace::vk
