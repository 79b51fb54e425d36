#include <array>

#include "rayspace/sim/device.h"

namespace rayspace::sim {
namespace {
constexpr std::array<const char*, kCheckerCount> kNames = {"racecheck", "initcheck", "synccheck", "memcheck"};
}  // namespace

const char* CheckerName(Checker c) { return kNames[static_cast<int>(c)]; }

std::string Checks::ToString() const {
  if (bits == 0xf) return "all";
  if (bits == 0) return "none";
  std::string s;
  for (int i = 0; i < kCheckerCount; ++i)
    if (bits >> i & 1u) {
      if (!s.empty()) s += ',';
      s += kNames[i];
    }
  return s;
}

std::optional<Checks> ParseChecks(std::string_view list, std::string& error) {
  if (list == "all") return Checks{};
  if (list == "none") return Checks::None();
  Checks c = Checks::None();
  while (!list.empty()) {
    const std::size_t comma = list.find(',');
    const std::string_view name = list.substr(0, comma);
    int found = -1;
    for (int i = 0; i < kCheckerCount; ++i)
      if (name == kNames[i]) found = i;
    if (found < 0) {
      error = "'" + std::string(name) + "' is not a checker (racecheck, initcheck, synccheck, memcheck, all, none)";
      return std::nullopt;
    }
    c.bits |= static_cast<std::uint8_t>(1u << found);
    list = comma == std::string_view::npos ? std::string_view() : list.substr(comma + 1);
    if (comma != std::string_view::npos && list.empty()) {
      error = "a checker list ends with ','";
      return std::nullopt;
    }
  }
  if (c.bits == 0) {
    error = "an empty checker list";
    return std::nullopt;
  }
  return c;
}

}  // namespace rayspace::sim
