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

}  // namespace rayspace::sim
