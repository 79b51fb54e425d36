#include "faithful_args.h"

#include <CLI/CLI.hpp>
#include <fmt/format.h>

namespace rayspace::app {

int MaxHashBits() { return (layout::kHashKeyBits - emu::HashConfig{}.light_bits) / 2; }

void AddFaithfulOptions(CLI::App& command, FaithfulArgs& args) {
  command
      .add_option("--hash-order", args.hash_order,
                  "Direction part of the CRSH hash keys: interleaved (polar and azimuth bits alternate) or polar-first "
                  "(all polar bits above the azimuth's, as the thesis prints it)")
      ->check(CLI::IsMember({"interleaved", "polar-first"}))
      ->capture_default_str();
  command
      .add_option("--hash-bits", args.hash_bits,
                  fmt::format("Shadow hash keys: cells bits per angle, polar and azimuth (1 to {}: the light index takes "
                              "{} of the key's {} bits)",
                              MaxHashBits(), emu::HashConfig{}.light_bits, layout::kHashKeyBits))
      ->check(CLI::Range(1, MaxHashBits()))
      ->capture_default_str();
}

void ApplyFaithful(const FaithfulArgs& args, emu::HierarchyConfig& hc) {
  hc.hash.order = args.hash_order == "polar-first" ? layout::kHashOrderPolarFirst : layout::kHashOrderInterleaved;
  hc.hash.polar_bits = hc.hash.azimuth_bits = args.hash_bits;
}

}  // namespace rayspace::app
