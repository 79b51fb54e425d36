// The reduce kernel against the stream's flagged values, on streams whose components outnumber the
// subgroups of kReduceStrideGroups workgroups, so that Local and Concat stride from component to
// component.
#include <doctest/doctest.h>

#include <memory>
#include <random>
#include <vector>

#include "rayspace/contract.h"
#include "rayspace/emu/hierarchy.h"
#include "rayspace/gpu/passes.h"

namespace rayspace {

TEST_CASE("reduce: streams of more components than the launched subgroups keep every flagged value in order") {
  std::unique_ptr<gpu_backend::VulkanPasses> gpu;
  const vk::Status created = gpu_backend::VulkanPasses::Create(-1, {}, gpu);
  INFO("Vulkan: " << created.message);
  REQUIRE(created);
  std::mt19937 rng(17);
  const std::size_t n = 1'100'003;
  std::vector<std::uint8_t> flags(n);
  std::vector<std::uint32_t> values(n), expect;
  for (std::size_t i = 0; i < n; ++i) {
    flags[i] = rng() % 29 == 0 || (i / 50000) % 7 == 3;  // sparse, with dense stretches
    values[i] = static_cast<std::uint32_t>(i * 2654435761u);
    if (flags[i]) expect.push_back(values[i]);
  }
  // Subgroups launched: at most the groups times the default local size of 64 (subgroups of one lane).
  const std::size_t launched = std::size_t{layout::kReduceStrideGroups} * 64;
  for (const int s : {1, 64}) {
    CAPTURE(s);
    REQUIRE((n + s - 1) / s > launched);
    std::vector<std::uint32_t> out;
    const emu::call::Reduce call{.reduction = emu::Reduction::kHierarchical, .component = s, .flags = flags, .values = values};
    const vk::Status st = gpu->Run(call, out);
    INFO(st.message);
    REQUIRE(st);
    CHECK(out == expect);
    CHECK(emu::ReduceHierarchical(flags, values, s) == expect);
  }
}

}  // namespace rayspace
