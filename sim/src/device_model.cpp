#include <array>
#include <charconv>
#include <utility>

#include <fmt/format.h>

#include "rayspace/sim/device.h"

namespace rayspace::sim {
namespace {

// "NAME" (seed 1) or "NAME:SEED" for one of `seeded`; nullopt with `error` set when a NAME is
// followed by a seed that is not one, or unset when no NAME matches.
template <class E, std::size_t N>
std::optional<std::pair<E, std::uint64_t>> ParseSeeded(std::string_view text, const std::array<std::pair<std::string_view, E>, N>& seeded,
                                                       std::string& error) {
  for (const auto& [name, value] : seeded) {
    if (text == name) return std::pair{value, std::uint64_t{1}};
    if (!text.starts_with(name) || text.size() <= name.size() || text[name.size()] != ':') continue;
    const std::string_view digits = text.substr(name.size() + 1);
    std::uint64_t seed = 0;
    const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), seed);
    if (!digits.empty() && ec == std::errc() && end == digits.data() + digits.size()) return std::pair{value, seed};
    error = "the seed '" + std::string(digits) + "' is not an unsigned 64-bit integer";
    return std::nullopt;
  }
  return std::nullopt;
}

}  // namespace

std::string DeviceModelChoice::ToString() const {
  if (model == DeviceModel::kLavapipe) return "lavapipe";
  return fmt::format("{}:{}", model == DeviceModel::kWorst ? "worst" : "worst-nearest", seed);
}

std::optional<DeviceModelChoice> ParseDeviceModel(std::string_view text, std::string& error) {
  if (text == "lavapipe") return DeviceModelChoice{};
  error.clear();
  constexpr std::array<std::pair<std::string_view, DeviceModel>, 2> kSeeded = {
      {{"worst", DeviceModel::kWorst}, {"worst-nearest", DeviceModel::kWorstNearest}}};
  if (const auto m = ParseSeeded(text, kSeeded, error)) return DeviceModelChoice{m->first, m->second};
  if (error.empty()) error = "'" + std::string(text) + "' is not a device model (lavapipe, worst, worst-nearest, each but lavapipe with :SEED)";
  return std::nullopt;
}

std::string SubgroupLayoutChoice::ToString() const {
  const std::string at = kernel.empty() ? "" : "@" + kernel;
  if (layout == SubgroupLayout::kLinear) return "linear" + at;
  return fmt::format("{}:{}{}", layout == SubgroupLayout::kShuffled ? "shuffled" : "partial", seed, at);
}

std::optional<SubgroupLayoutChoice> ParseSubgroupLayout(std::string_view text, std::string& error) {
  if (const std::size_t at = text.find('@'); at != std::string_view::npos) {
    const std::string_view kernel = text.substr(at + 1);
    if (kernel.empty() || kernel.find_first_not_of("abcdefghijklmnopqrstuvwxyz0123456789_.") != std::string_view::npos) {
      error = "'" + std::string(kernel) + "' after '@' is not a kernel name";
      return std::nullopt;
    }
    std::optional<SubgroupLayoutChoice> c = ParseSubgroupLayout(text.substr(0, at), error);
    if (c) c->kernel = std::string(kernel);
    return c;
  }
  if (text == "linear") return SubgroupLayoutChoice{};
  error.clear();
  constexpr std::array<std::pair<std::string_view, SubgroupLayout>, 2> kSeeded = {
      {{"shuffled", SubgroupLayout::kShuffled}, {"partial", SubgroupLayout::kPartial}}};
  if (const auto l = ParseSeeded(text, kSeeded, error)) return SubgroupLayoutChoice{l->first, l->second, ""};
  if (error.empty()) error = "'" + std::string(text) + "' is not a subgroup layout (linear, shuffled, partial, the last two with :SEED)";
  return std::nullopt;
}

}  // namespace rayspace::sim
