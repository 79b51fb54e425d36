#include "rayspace/sim/storage_check.h"

#include <fmt/format.h>

namespace rayspace::sim {

StorageCheck::StorageCheck(const std::vector<std::size_t>& binding_words) {
  for (std::size_t words : binding_words) pages_.emplace_back((words + kPageWords - 1) / kPageWords);
}
StorageCheck::~StorageCheck() = default;

void StorageCheck::BeginWorkgroup(std::uint32_t workgroup) {
  group_ = workgroup;
  interval_ = 0;
}

StorageCheck::Word& StorageCheck::At(std::uint32_t binding, std::size_t word) {
  std::unique_ptr<Word[]>& page = pages_[binding][word / kPageWords];
  if (!page) page = std::make_unique<Word[]>(kPageWords);
  return page[word % kPageWords];
}

std::optional<Finding> StorageCheck::Access(std::uint32_t binding, std::size_t word, std::uint32_t invocation, AccessKind kind) {
  if (kind == AccessKind::kAtomic || binding >= pages_.size() || word / kPageWords >= pages_[binding].size()) return std::nullopt;
  Word& w = At(binding, word);
  const auto who = [&](std::uint32_t group, std::uint32_t inv) {
    return group == group_ ? fmt::format("invocation {}", inv) : fmt::format("invocation {} of workgroup {}", inv, group);
  };
  const char* verb = kind == AccessKind::kRead ? "reads" : "writes";
  // The last store is unordered with this access: another workgroup's, or another invocation's in
  // this barrier interval.
  if (w.w_group != kNobody && (w.w_group != group_ || (w.w_interval == interval_ && w.w_inv != invocation)))
    return Finding{Checker::kRacecheck, fmt::format("invocation {} of workgroup {} {} binding {} word {}, which {} wrote with no barrier between", invocation,
                       group_, verb, binding, word, who(w.w_group, w.w_inv))};
  if (kind == AccessKind::kRead) {
    if (w.r_group == kNobody || (w.r_group == group_ && w.r_interval != interval_)) {
      w.r_group = group_;
      w.r_interval = interval_;
      w.r_inv = invocation;
    } else if (w.r_group != group_) {
      w.r_group = kMany;
    } else if (w.r_inv != invocation) {
      w.r_inv = kMany;
    }
    return std::nullopt;
  }
  if (w.r_group == kMany || (w.r_group != kNobody && w.r_group != group_))
    return Finding{Checker::kRacecheck, fmt::format("invocation {} of workgroup {} writes binding {} word {}, which invocations of other workgroups read in "
                       "this dispatch",
                       invocation, group_, binding, word)};
  if (w.r_group == group_ && w.r_interval == interval_ && w.r_inv != invocation)
    return Finding{Checker::kRacecheck, w.r_inv == kMany ? fmt::format("invocation {} of workgroup {} writes binding {} word {}, which other invocations read "
                                          "with no barrier between",
                                          invocation, group_, binding, word)
                            : fmt::format("invocation {} of workgroup {} writes binding {} word {}, which invocation {} read "
                                          "with no barrier between",
                                          invocation, group_, binding, word, w.r_inv)};
  w.w_group = group_;
  w.w_interval = interval_;
  w.w_inv = invocation;
  w.r_group = kNobody;
  return std::nullopt;
}

}  // namespace rayspace::sim
