// racecheck on storage buffers over one dispatch, fed by the executor's events: every load and store
// of a storage-buffer word with its invocation and workgroup, and every barrier that orders storage
// memory in a workgroup (an OpControlBarrier whose semantics, or an OpMemoryBarrier's executed since
// the previous barrier, include UniformMemory: GLSL's barrier() alone orders only shared memory).
// Two accesses to one word, at least one a store, by different invocations race unless such a barrier
// of their workgroup lies between them; invocations of different workgroups of one dispatch are never
// ordered. Atomics race with nothing. The shadow state is kept in pages allocated on first touch.
#pragma once
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "rayspace/sim/shared_check.h"

namespace rayspace::sim {

class StorageCheck {
 public:
  // One entry per binding: its size in 4-byte words.
  explicit StorageCheck(const std::vector<std::size_t>& binding_words);
  ~StorageCheck();
  // A workgroup begins (its linear index in the dispatch, for reports).
  void BeginWorkgroup(std::uint32_t workgroup);
  // Every invocation of the workgroup passed a barrier that orders storage memory.
  void Barrier() { ++interval_; }
  // An access of local invocation `invocation` to word `word` of binding `binding`: a racecheck
  // finding or nothing.
  std::optional<Finding> Access(std::uint32_t binding, std::size_t word, std::uint32_t invocation, AccessKind kind);

 private:
  static constexpr std::uint32_t kNobody = ~0u, kMany = ~0u - 1;
  struct Word {
    std::uint32_t w_group = kNobody, w_interval = 0, w_inv = 0;  // the last store
    std::uint32_t r_group = kNobody, r_interval = 0, r_inv = 0;  // loads since: one workgroup or kMany; one invocation or kMany
  };
  static constexpr std::size_t kPageWords = 1024;
  Word& At(std::uint32_t binding, std::size_t word);
  std::vector<std::vector<std::unique_ptr<Word[]>>> pages_;  // by binding, by page
  std::uint32_t group_ = 0, interval_ = 0;
};

}  // namespace rayspace::sim
