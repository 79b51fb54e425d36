#include "rayspace/sim/module_tools.h"

#include <spirv-tools/libspirv.hpp>
#include <spirv-tools/optimizer.hpp>

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

std::vector<std::uint32_t> WithoutDebugInfo(std::span<const std::uint32_t> spirv, const std::string& what) {
  spvtools::Optimizer opt(SPV_ENV_VULKAN_1_2);
  std::string first;
  opt.SetMessageConsumer([&first](spv_message_level_t, const char*, const spv_position_t&, const char* message) {
    if (first.empty()) first = OneLine(message);
  });
  opt.RegisterPass(spvtools::CreateStripDebugInfoPass()).RegisterPass(spvtools::CreateCompactIdsPass());
  std::vector<std::uint32_t> out;
  if (!opt.Run(spirv.data(), spirv.size(), &out)) ThrowInput("{}: spirv-opt --strip-debug failed: {}", what, first);
  return out;
}

}  // namespace rayspace::sim
