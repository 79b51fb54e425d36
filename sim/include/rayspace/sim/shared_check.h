// racecheck and initcheck on a workgroup's shared memory, fed by the executor's events: every load,
// store and atomic on a Workgroup variable (word by word, with the invocation), and every barrier
// the whole workgroup passes. Between two barriers any two invocations are unordered, lanes of one
// subgroup included (lockstep execution is a choice of this simulator, not a guarantee of Vulkan):
// two accesses to one word by different invocations in one such interval, at least one a store, are
// a race; atomics race with nothing. A load of a word no invocation of the workgroup has stored is a
// read of undefined memory.
#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "rayspace/sim/device.h"

namespace rayspace::sim {

enum class AccessKind : std::uint8_t { kRead, kWrite, kAtomic };

// What a checker found, in words that name the invocations and the word (not the kernel).
struct Finding {
  Checker checker;
  std::string what;
};

class SharedCheck {
 public:
  // A workgroup begins: `words` of shared memory, none written; findings of the checkers in `checks`.
  void Begin(std::size_t words, Checks checks);
  // Every invocation passed a barrier: accesses before it are ordered before those after.
  void Barrier() { ++epoch_; }
  // An access of `invocation` to shared word `word`: a racecheck or initcheck finding, or nothing.
  std::optional<Finding> Access(std::size_t word, std::uint32_t invocation, AccessKind kind);

 private:
  static constexpr std::uint32_t kNobody = ~0u, kMany = ~0u - 1;
  struct Word {
    std::uint32_t write_epoch = 0, writer = kNobody;  // the last store's interval and invocation
    std::uint32_t read_epoch = 0, reader = kNobody;   // loads in read_epoch: one invocation, or kMany
    bool written = false;
  };
  std::vector<Word> words_;
  std::uint32_t epoch_ = 1;
  bool race_ = true, init_ = true;
};

}  // namespace rayspace::sim
