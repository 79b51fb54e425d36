#include "rayspace/sim/shared_check.h"

#include <fmt/format.h>

namespace rayspace::sim {

void SharedCheck::Begin(std::size_t words, Checks checks) {
  words_.assign(words, Word{});
  epoch_ = 1;
  race_ = checks.On(Checker::kRacecheck);
  init_ = checks.On(Checker::kInitcheck);
}

std::optional<Finding> SharedCheck::Access(std::size_t word, std::uint32_t invocation, AccessKind kind) {
  if (word >= words_.size() || kind == AccessKind::kAtomic) {
    if (word < words_.size()) words_[word].written = true;
    return std::nullopt;
  }
  Word& w = words_[word];
  const bool wrote_now = w.write_epoch == epoch_ && w.writer != kNobody;
  if (kind == AccessKind::kRead) {
    if (!w.written && init_) return Finding{Checker::kInitcheck, fmt::format("invocation {} reads shared word {}, which no invocation of its workgroup wrote", invocation, word)};
    if (race_ && wrote_now && w.writer != invocation)
      return Finding{Checker::kRacecheck, fmt::format("invocation {} reads shared word {}, which invocation {} wrote with no barrier between", invocation, word,
                                                      w.writer)};
    if (w.read_epoch != epoch_) {
      w.read_epoch = epoch_;
      w.reader = invocation;
    } else if (w.reader != invocation) {
      w.reader = kMany;
    }
    return std::nullopt;
  }
  if (race_ && wrote_now && w.writer != invocation)
    return Finding{Checker::kRacecheck, fmt::format("invocation {} writes shared word {}, which invocation {} wrote with no barrier between",
                                                    invocation, word, w.writer)};
  if (race_ && w.read_epoch == epoch_ && w.reader != invocation)
    return Finding{Checker::kRacecheck,
                   w.reader == kMany
                       ? fmt::format("invocation {} writes shared word {}, which other invocations read with no barrier between", invocation, word)
                       : fmt::format("invocation {} writes shared word {}, which invocation {} read with no barrier between", invocation, word,
                                     w.reader)};
  w.write_epoch = epoch_;
  w.writer = invocation;
  w.written = true;
  return std::nullopt;
}

}  // namespace rayspace::sim
