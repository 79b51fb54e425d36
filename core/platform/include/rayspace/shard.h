// A slice of a long run for one machine (`reproduce --shard`, `mutate --shard`): shard I of N takes
// items I, I+N, I+2N, ... of the run's deterministic order; `merge` puts the N results back in order.
#pragma once
#include <compare>
#include <cstddef>
#include <string>

namespace rayspace {

struct Shard {
  int index = 0, count = 1;
  auto operator<=>(const Shard&) const = default;
  bool Holds(std::size_t item) const { return item % static_cast<std::size_t>(count) == static_cast<std::size_t>(index); }
};
// "I/N" with 0 <= I < N; throws InputError naming --shard.
Shard ParseShard(const std::string& text);

}  // namespace rayspace
