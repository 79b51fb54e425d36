#include "rayspace/sim/grammar.h"

#include <map>
#include <utility>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "rayspace_sim_grammar.inc"

namespace rayspace::sim {
namespace {

struct Tables {
  // kind -> value -> name, and kind -> names.
  std::map<std::string, std::map<std::uint32_t, std::string>, std::less<>> by_value;
};

std::string Joined(const char* const* pieces, std::size_t n) {
  std::string s;
  for (std::size_t i = 0; i < n; ++i) s += pieces[i];
  return s;
}

std::uint32_t ValueOf(const nlohmann::json& v) {
  // Bit-enum values are written as hex strings ("0x0004"), value enums as numbers.
  return v.is_string() ? static_cast<std::uint32_t>(std::stoul(v.get<std::string>(), nullptr, 0)) : v.get<std::uint32_t>();
}

Tables Load() {
  Tables t;
  const auto core = nlohmann::json::parse(Joined(kCoreGrammarJson, std::size(kCoreGrammarJson)));
  auto& ops = t.by_value[std::string(kOpcode)];
  for (const auto& in : core.at("instructions")) ops.emplace(in.at("opcode").get<std::uint32_t>(), in.at("opname").get<std::string>());
  for (const auto& kind : core.at("operand_kinds")) {
    if (!kind.contains("enumerants")) continue;
    auto& names = t.by_value[kind.at("kind").get<std::string>()];
    // Aliases share a value: the first listed name is the one shown.
    for (const auto& e : kind.at("enumerants")) names.emplace(ValueOf(e.at("value")), e.at("enumerant").get<std::string>());
  }
  const auto glsl = nlohmann::json::parse(Joined(kGlslGrammarJson, std::size(kGlslGrammarJson)));
  auto& ext = t.by_value[std::string(kGlslStd450)];
  for (const auto& in : glsl.at("instructions")) ext.emplace(in.at("opcode").get<std::uint32_t>(), in.at("opname").get<std::string>());
  return t;
}

const Tables& Grammar() {
  static const Tables t = Load();
  return t;
}

}  // namespace

std::string NameOf(std::string_view kind, std::uint32_t value) {
  const auto k = Grammar().by_value.find(kind);
  if (k != Grammar().by_value.end())
    if (const auto v = k->second.find(value); v != k->second.end()) return v->second;
  return fmt::format("{} {}", kind, value);
}

bool GrammarLists(std::string_view kind, std::string_view name) {
  const auto k = Grammar().by_value.find(kind);
  if (k == Grammar().by_value.end()) return false;
  for (const auto& [value, n] : k->second)
    if (n == name) return true;
  return false;
}

}  // namespace rayspace::sim
