#include "rayspace/workgroup.h"

#include <fmt/format.h>

#include <algorithm>

#include "rayspace/error.h"
#include "rayspace/parallel.h"
#include "rayspace/settings.h"

namespace rayspace::wg {
namespace {

constexpr std::size_t kReportCap = 64;

std::uint64_t SplitMix(std::uint64_t& s) {
  std::uint64_t z = (s += 0x9e3779b97f4a7c15ull);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return z ^ (z >> 31);
}

const char* AccessName(Access a) {
  switch (a) {
    case Access::kRead: return "read";
    case Access::kWrite: return "write";
    case Access::kAtomic: return "atomic";
  }
  return "?";
}

std::string InvName(std::uint32_t inv) {
  return inv == kNoInvocation ? std::string("-") : std::to_string(inv);
}

}  // namespace

Schedule GetSchedule() { return CurrentSettings().schedule; }
bool Checking() { return CurrentSettings().check; }
std::uint32_t LocalSize() { return CurrentSettings().local_size; }
std::uint32_t SubgroupSize() { return CurrentSettings().subgroup_size; }

const char* ToString(ReportKind k) {
  switch (k) {
    case ReportKind::kRace: return "race";
    case ReportKind::kUninitialisedRead: return "uninitialised read";
    case ReportKind::kOutOfBounds: return "out of bounds";
    case ReportKind::kDivergentBarrier: return "divergent barrier";
    case ReportKind::kBarrierInPhase: return "barrier inside a phase";
    case ReportKind::kInvalidLane: return "invalid lane";
  }
  return "?";
}

std::size_t CheckResult::Count(ReportKind k) const {
  return static_cast<std::size_t>(std::count_if(reports.begin(), reports.end(), [k](const Report& r) { return r.kind == k; }));
}

std::string CheckResult::Summary() const {
  std::string s;
  for (const Report& r : reports) s += r.message + "\n";
  if (dropped) s += fmt::format("({} more reports dropped)\n", dropped);
  return s;
}

// ---- Shared arrays ------------------------------------------------------------------------------------

SharedBase::SharedBase(Workgroup* wg, std::string name, std::uint32_t count)
    : wg_(wg), name_(std::move(name)), count_(count), check_(wg->checking()), words_(wg->checking() ? count : 0),
      written_(wg->checking() ? count : 0, 0) {}

bool SharedBase::TouchChecked(std::uint32_t idx, Access a) {
  const std::uint32_t inv = wg_->current();
  if (idx >= count_) {
    wg_->AddReport(ReportKind::kOutOfBounds, name_, idx, inv, kNoInvocation,
                   fmt::format("{} of {} elements", AccessName(a), count_));
    return false;
  }
  if (!check_ || inv == kNoInvocation) return true;
  if (a != Access::kWrite && written_[idx] == 0) {
    written_[idx] = 2;  // report once per word
    wg_->AddReport(ReportKind::kUninitialisedRead, name_, idx, inv, kNoInvocation,
                   fmt::format("{} of a word no invocation has written", AccessName(a)));
  }
  if (a != Access::kRead) written_[idx] = 1;
  Word& w = words_[idx];
  if (w.interval != wg_->interval()) {
    w = Word{};
    w.interval = wg_->interval();
    for (int k = 0; k < 2; ++k) w.reader[k] = w.writer[k] = w.atomic[k] = kNoInvocation;
  }
  if (!w.raced) Conflict(idx, w, inv, a);
  std::uint32_t* slot = a == Access::kRead ? w.reader : a == Access::kWrite ? w.writer : w.atomic;
  if (slot[0] == kNoInvocation) {
    slot[0] = inv;
  } else if (slot[0] != inv && slot[1] == kNoInvocation) {
    slot[1] = inv;
  }
  return true;
}

void SharedBase::Conflict(std::uint32_t idx, Word& w, std::uint32_t inv, Access a) {
  auto other = [inv](const std::uint32_t* s) {
    if (s[0] != kNoInvocation && s[0] != inv) return s[0];
    if (s[1] != kNoInvocation && s[1] != inv) return s[1];
    return kNoInvocation;
  };
  // Plain writes conflict with everything; reads with writes and atomics; atomics with plain accesses.
  Access first = Access::kWrite;
  std::uint32_t o = other(w.writer);
  if (o == kNoInvocation && a != Access::kRead) o = other(w.reader), first = Access::kRead;
  if (o == kNoInvocation && a != Access::kAtomic) o = other(w.atomic), first = Access::kAtomic;
  if (o == kNoInvocation) return;
  w.raced = true;  // one report per word per barrier interval
  wg_->AddReport(ReportKind::kRace, name_, idx, o, inv,
                 fmt::format("invocation {} ({}) and invocation {} ({}) without a barrier between", o,
                             AccessName(first), inv, AccessName(a)));
}

// ---- Workgroup ------------------------------------------------------------------------------------------

Workgroup::Workgroup(const std::string& dispatch, std::uint32_t id, std::uint32_t groups,
                     std::uint32_t local_size, std::uint32_t subgroup_size, Schedule schedule, bool check)
    : dispatch_(dispatch), id_(id), groups_(groups), local_size_(local_size), subgroup_size_(subgroup_size),
      schedule_(schedule), check_(check), phase_barriers_(local_size, 0) {}

Workgroup::~Workgroup() = default;

Inv Workgroup::BeginPhase() {
  RS_CHECK_MSG(!in_phase_, "dispatch {}: Phase called inside a phase", dispatch_);
  in_phase_ = true;
  if (check_) std::fill(phase_barriers_.begin(), phase_barriers_.end(), 0u);
  if (order_.size() != local_size_ || schedule_.order == Order::kRandom) {
    order_.resize(local_size_);
    for (std::uint32_t l = 0; l < local_size_; ++l) order_[l] = l;
    if (schedule_.order == Order::kReverse) std::reverse(order_.begin(), order_.end());
  }
  if (schedule_.order == Order::kRandom) {
    // Fisher-Yates from SplitMix64 of (seed, workgroup, phase): the same for any thread count or library.
    std::uint64_t s = schedule_.seed ^ (std::uint64_t{id_} << 32) ^ (std::uint64_t{phase_} * 0x2545f4914f6cdd1dull);
    for (std::uint32_t l = local_size_; l > 1; --l) std::swap(order_[l - 1], order_[SplitMix(s) % l]);
  }
  Inv inv{};
  inv.workgroup_id = id_;
  inv.local_size = local_size_;
  inv.num_workgroups = groups_;
  inv.subgroup_size = subgroup_size_;
  return inv;
}

void Workgroup::EndPhase() {
  current_ = kNoInvocation;
  in_phase_ = false;
  CheckPhaseBarriers();
  ++phase_;
}

void Workgroup::Barrier() {
  if (in_phase_) {
    ++phase_barriers_[current_];
  } else {
    ++interval_;
  }
}

void Workgroup::CheckPhaseBarriers() {
  if (!check_) return;
  const auto hi = std::max_element(phase_barriers_.begin(), phase_barriers_.end());  // first with most
  const auto lo = std::min_element(phase_barriers_.begin(), phase_barriers_.end());  // first with fewest
  if (*hi == 0) return;
  if (*lo == *hi) {
    AddReport(ReportKind::kBarrierInPhase, "", 0, kNoInvocation, kNoInvocation,
              fmt::format("every invocation reached {} barrier(s) inside the phase; split the phase there", *hi));
    return;
  }
  const auto a = static_cast<std::uint32_t>(hi - phase_barriers_.begin());
  const auto b = static_cast<std::uint32_t>(lo - phase_barriers_.begin());
  AddReport(ReportKind::kDivergentBarrier, "", 0, a, b,
            fmt::format("invocation {} reached {} barrier(s), invocation {} reached {}", a, *hi, b, *lo));
}

void Workgroup::AddReport(ReportKind kind, const std::string& array, std::uint32_t word, std::uint32_t a,
                          std::uint32_t b, const std::string& detail) {
  if (reports_.size() >= kReportCap) {
    ++dropped_;
    return;
  }
  Report r{kind, dispatch_, id_, phase_, interval_, array, word, a, b, {}};
  const std::string where = array.empty() ? std::string() : fmt::format(" {}[{}]", array, word);
  r.message = fmt::format("{}: dispatch {} workgroup {} phase {} interval {}{} invocations {},{}: {}", ToString(kind),
                          dispatch_, id_, phase_, interval_, where, InvName(a), InvName(b), detail);
  reports_.push_back(std::move(r));
}

std::vector<Report> Workgroup::TakeReports(std::size_t* dropped) {
  *dropped = dropped_;
  return std::move(reports_);
}

// ---- Subgroups ------------------------------------------------------------------------------------------

void Workgroup::SubgroupBoundary() {
  RS_CHECK_MSG(!in_phase_, "dispatch {}: subgroup operations go between phases", dispatch_);
}

Private<glm::uvec4> Workgroup::SubgroupBallot(const wg::Private<bool>& pred) {
  SubgroupBoundary();
  wg::Private<glm::uvec4> out(local_size_, glm::uvec4(0));
  for (std::uint32_t base = 0; base < local_size_; base += subgroup_size_) {
    glm::uvec4 bits(0);
    const std::uint32_t end = std::min(local_size_, base + subgroup_size_);
    for (std::uint32_t l = base; l < end; ++l)
      if (pred[l]) bits[(l - base) / 32] |= 1u << ((l - base) % 32);
    for (std::uint32_t l = base; l < end; ++l) out[l] = bits;
  }
  return out;
}

namespace {
enum class Scan { kReduce, kInclusive, kExclusive };
}

static Private<std::uint32_t> SubgroupScan(const Private<std::uint32_t>& x, std::uint32_t size, Scan kind) {
  const std::uint32_t n = x.size();
  Private<std::uint32_t> out(n);
  for (std::uint32_t base = 0; base < n; base += size) {
    const std::uint32_t end = std::min(n, base + size);
    std::uint32_t sum = 0;
    for (std::uint32_t l = base; l < end; ++l) {
      if (kind == Scan::kExclusive) out[l] = sum;
      sum += x[l];
      if (kind == Scan::kInclusive) out[l] = sum;
    }
    if (kind == Scan::kReduce)
      for (std::uint32_t l = base; l < end; ++l) out[l] = sum;
  }
  return out;
}

Private<std::uint32_t> Workgroup::SubgroupAdd(const wg::Private<std::uint32_t>& x) {
  SubgroupBoundary();
  return SubgroupScan(x, subgroup_size_, Scan::kReduce);
}
Private<std::uint32_t> Workgroup::SubgroupInclusiveAdd(const wg::Private<std::uint32_t>& x) {
  SubgroupBoundary();
  return SubgroupScan(x, subgroup_size_, Scan::kInclusive);
}
Private<std::uint32_t> Workgroup::SubgroupExclusiveAdd(const wg::Private<std::uint32_t>& x) {
  SubgroupBoundary();
  return SubgroupScan(x, subgroup_size_, Scan::kExclusive);
}

Private<bool> Workgroup::SubgroupElect() {
  SubgroupBoundary();
  wg::Private<bool> out(local_size_, false);
  for (std::uint32_t l = 0; l < local_size_; l += subgroup_size_) out[l] = true;
  return out;
}

// ---- Dispatch -------------------------------------------------------------------------------------------

CheckResult Dispatch(const std::string& name, std::uint32_t groups, std::uint32_t local_size,
                     const std::function<void(Workgroup&)>& kernel, const DispatchOptions& options) {
  const std::uint32_t sg = options.subgroup_size.value_or(SubgroupSize());
  RS_CHECK_MSG(sg >= 1 && sg <= 128 && (sg & (sg - 1)) == 0, "dispatch {}: subgroup size {}", name, sg);
  RS_CHECK_MSG(local_size >= 1, "dispatch {}: empty workgroup", name);
  const Schedule schedule = options.schedule.value_or(GetSchedule());
  const bool check = options.check.value_or(Checking());
  std::vector<std::vector<Report>> per(groups);
  std::vector<std::size_t> dropped(groups, 0);
  ParallelFor(groups, [&](std::size_t g) {
    Workgroup w(name, static_cast<std::uint32_t>(g), groups, local_size, sg, schedule, check);
    kernel(w);
    per[g] = w.TakeReports(&dropped[g]);
  });
  CheckResult result;
  for (std::uint32_t g = 0; g < groups; ++g) {
    for (Report& r : per[g]) result.reports.push_back(std::move(r));
    result.dropped += dropped[g];
  }
  if (options.throw_on_report && !result.ok()) {
    // The message first: the order in which a call's arguments are evaluated is unspecified, and the
    // result is moved into the exception.
    std::string what = fmt::format("dispatch {}: {} checker report(s); first: {}", name, result.reports.size() + result.dropped,
                                   result.reports.empty() ? std::string("-") : result.reports.front().message);
    throw CheckError(what, std::move(result));
  }
  return result;
}

}  // namespace rayspace::wg
