#include <charconv>
#include <utility>

#include <fmt/format.h>

#include "rayspace/sim/device.h"

namespace rayspace::sim {

std::string DeviceModelChoice::ToString() const {
  if (model == DeviceModel::kLavapipe) return "lavapipe";
  return fmt::format("{}:{}", model == DeviceModel::kWorst ? "worst" : "worst-nearest", seed);
}

std::optional<DeviceModelChoice> ParseDeviceModel(std::string_view text, std::string& error) {
  if (text == "lavapipe") return DeviceModelChoice{};
  for (const auto& [name, model] : {std::pair{std::string_view("worst"), DeviceModel::kWorst},
                                    std::pair{std::string_view("worst-nearest"), DeviceModel::kWorstNearest}}) {
    if (text == name) return DeviceModelChoice{model, 1};
    if (!text.starts_with(name) || text.size() <= name.size() || text[name.size()] != ':') continue;
    const std::string_view digits = text.substr(name.size() + 1);
    std::uint64_t seed = 0;
    const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), seed);
    if (!digits.empty() && ec == std::errc() && end == digits.data() + digits.size()) return DeviceModelChoice{model, seed};
    error = "the seed '" + std::string(digits) + "' is not an unsigned 64-bit integer";
    return std::nullopt;
  }
  error = "'" + std::string(text) + "' is not a device model (lavapipe, worst, worst-nearest, each but lavapipe with :SEED)";
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
  for (const auto& [name, layout] : {std::pair{std::string_view("shuffled"), SubgroupLayout::kShuffled},
                                     std::pair{std::string_view("partial"), SubgroupLayout::kPartial}}) {
    if (text == name) return SubgroupLayoutChoice{layout, 1};
    if (!text.starts_with(name) || text.size() <= name.size() || text[name.size()] != ':') continue;
    const std::string_view digits = text.substr(name.size() + 1);
    std::uint64_t seed = 0;
    const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), seed);
    if (!digits.empty() && ec == std::errc() && end == digits.data() + digits.size()) return SubgroupLayoutChoice{layout, seed};
    error = "the seed '" + std::string(digits) + "' is not an unsigned 64-bit integer";
    return std::nullopt;
  }
  error = "'" + std::string(text) + "' is not a subgroup layout (linear, shuffled, partial, the last two with :SEED)";
  return std::nullopt;
}

}  // namespace rayspace::sim
