#include "rayspace/sim/shared_check.h"

#include <fmt/format.h>

namespace rayspace::sim {

void SharedCheck::Begin(std::size_t words) {
  words_.assign(words, Word{});
  epoch_ = 1;
}

std::optional<std::string> SharedCheck::Access(std::size_t word, std::uint32_t invocation, AccessKind kind) {
  if (word >= words_.size() || kind == AccessKind::kAtomic) {
    if (word < words_.size()) words_[word].written = true;
    return std::nullopt;
  }
  Word& w = words_[word];
  const bool wrote_now = w.write_epoch == epoch_ && w.writer != kNobody;
  if (kind == AccessKind::kRead) {
    if (!w.written) return fmt::format("initcheck: invocation {} reads shared word {}, which no invocation of its workgroup wrote", invocation, word);
    if (wrote_now && w.writer != invocation)
      return fmt::format("racecheck: invocation {} reads shared word {}, which invocation {} wrote with no barrier between", invocation, word,
                         w.writer);
    if (w.read_epoch != epoch_) {
      w.read_epoch = epoch_;
      w.reader = invocation;
    } else if (w.reader != invocation) {
      w.reader = kMany;
    }
    return std::nullopt;
  }
  if (wrote_now && w.writer != invocation)
    return fmt::format("racecheck: invocation {} writes shared word {}, which invocation {} wrote with no barrier between", invocation, word,
                       w.writer);
  if (w.read_epoch == epoch_ && w.reader != invocation)
    return w.reader == kMany
               ? fmt::format("racecheck: invocation {} writes shared word {}, which other invocations read with no barrier between", invocation, word)
               : fmt::format("racecheck: invocation {} writes shared word {}, which invocation {} read with no barrier between", invocation, word,
                             w.reader);
  w.write_epoch = epoch_;
  w.writer = invocation;
  w.written = true;
  return std::nullopt;
}

}  // namespace rayspace::sim
