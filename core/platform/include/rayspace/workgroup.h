// Workgroup execution model for C++ mirrors of GLSL compute kernels that use shared memory, barriers,
// subgroup operations and atomics (docs/workgroups.md). Beside ParallelFor, not instead of it.
//
// A dispatch runs G workgroups of L invocations (1-D). The kernel callback runs once per workgroup and
// is written as the GLSL kernel's sequence of phases separated by barriers:
//
//   auto result = wg::Dispatch("scan.block", groups, 256, [&](wg::Workgroup& w) {
//     auto& tile = w.Shared<uint32_t>(256);      // shared uint tile[256];
//     auto x = w.Private<uint32_t>();            // a local variable that lives across barriers
//     w.Phase([&](wg::Inv& i) { tile[i.local_id] = in[i.global_id]; });
//     w.Barrier();                               // barrier();
//     w.Phase([&](wg::Inv& i) { x[i] = tile[i.local_id]; });
//     auto s = w.SubgroupInclusiveAdd(x);        // uint s = subgroupInclusiveAdd(x);
//     ...
//   });
//
// Workgroups run in parallel through ParallelFor; the invocations of one phase run one at a time on
// one thread, in the schedule's order (forward, reverse or a seeded random permutation per phase).
// Shared-memory accesses are checked for races, reads of never-written words, out-of-bounds indices
// and divergent barriers; the reports come back in the CheckResult (or as an exception, on request).
#pragma once
#include <algorithm>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <functional>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include <glm/vec4.hpp>

#include "rayspace/settings.h"

namespace rayspace::wg {

// ---- Schedule and device shape ----------------------------------------------------------------------

// The schedule, checking and device shape in force (rayspace/settings.h): the defaults of dispatches
// that do not set their own, as the Vulkan side's --local-size and the device's subgroup size.
Schedule GetSchedule();
bool Checking();
std::uint32_t LocalSize();
std::uint32_t SubgroupSize();

// ---- Checker reports --------------------------------------------------------------------------------

enum class ReportKind {
  kRace,               // two invocations, same word, same barrier interval, at least one plain write
  kUninitialisedRead,  // a read (or atomic) of a shared word no invocation has written
  kOutOfBounds,        // shared index past the array's count (reads return poison, writes are dropped)
  kDivergentBarrier,   // a barrier reached by some invocations of a phase and not others
  kBarrierInPhase,     // a barrier reached by every invocation inside a phase: split the phase there
  kInvalidLane,        // broadcast/shuffle from a lane that does not exist in the subgroup
};
const char* ToString(ReportKind k);

inline constexpr std::uint32_t kNoInvocation = 0xffffffffu;

struct Report {
  ReportKind kind;
  std::string dispatch;
  std::uint32_t workgroup = 0;
  std::uint32_t phase = 0;     // index of the Phase call (0-based) where the fault was seen
  std::uint32_t interval = 0;  // barrier interval (number of wg barriers before it)
  std::string array;           // shared array ("shared#k" or the name given to Shared)
  std::uint32_t word = 0;      // element index in that array
  std::uint32_t inv_a = kNoInvocation;  // local ids: the earlier access / an invocation that reached
  std::uint32_t inv_b = kNoInvocation;  // the later access / an invocation that did not reach
  std::string message;         // one line, every field above spelled out
};

struct CheckResult {
  std::vector<Report> reports;        // in workgroup order, then in the order seen
  std::size_t dropped = 0;            // reports past the per-workgroup cap (64)
  bool ok() const { return reports.empty() && dropped == 0; }
  std::size_t Count(ReportKind k) const;
  std::string Summary() const;        // one line per report
};

class CheckError : public std::runtime_error {
 public:
  CheckError(const std::string& what, CheckResult r) : std::runtime_error(what), result(std::move(r)) {}
  CheckResult result;
};

struct DispatchOptions {
  std::optional<std::uint32_t> subgroup_size = std::nullopt;  // overrides Settings::subgroup_size
  std::optional<Schedule> schedule = std::nullopt;  // overrides Settings::schedule for this dispatch
  std::optional<bool> check = std::nullopt;  // overrides Settings::check for this dispatch
  bool throw_on_report = false;        // throw CheckError instead of returning a non-ok result
};

// ---- Invocation context -----------------------------------------------------------------------------

struct Inv {
  std::uint32_t global_id;      // gl_GlobalInvocationID.x
  std::uint32_t local_id;       // gl_LocalInvocationID.x
  std::uint32_t workgroup_id;   // gl_WorkGroupID.x
  std::uint32_t subgroup_id;    // gl_SubgroupID = local_id / subgroup_size
  std::uint32_t lane;           // gl_SubgroupInvocationID = local_id % subgroup_size
  std::uint32_t local_size;     // gl_WorkGroupSize.x
  std::uint32_t num_workgroups; // gl_NumWorkGroups.x
  std::uint32_t subgroup_size;  // gl_SubgroupSize
};

// A local variable of every invocation (GLSL locals live across barriers; a phase is a lambda, so a
// value that outlives one phase is kept here). x[i] with i the Inv, or x[local_id].
template <typename T>
class Private {
 public:
  explicit Private(std::uint32_t n, T init = T{}) : v_(n, Slot{init}) {}
  T& operator[](const Inv& i) { return v_[i.local_id].v; }
  const T& operator[](const Inv& i) const { return v_[i.local_id].v; }
  T& operator[](std::uint32_t local_id) { return v_[local_id].v; }
  const T& operator[](std::uint32_t local_id) const { return v_[local_id].v; }
  std::uint32_t size() const { return static_cast<std::uint32_t>(v_.size()); }

 private:
  struct Slot {
    T v;
  };  // not std::vector<bool>'s packed bits: x[i] is a real bool&
  std::vector<Slot> v_;
};

// ---- Shared memory ----------------------------------------------------------------------------------

class Workgroup;
enum class Access : std::uint8_t { kRead, kWrite, kAtomic };

// The untyped part of a shared array: its checker state. Per word, the invocations that read, wrote and
// used atomics on it in the current barrier interval (two distinct ones of each suffice to find a
// conflict with any third), and whether it has ever been written.
class SharedBase {
 public:
  SharedBase(Workgroup* wg, std::string name, std::uint32_t count);
  virtual ~SharedBase() = default;  // the workgroup owns its arrays through SharedBase pointers
  SharedBase(const SharedBase&) = delete;
  SharedBase& operator=(const SharedBase&) = delete;
  const std::string& name() const { return name_; }
  std::uint32_t count() const { return count_; }

 protected:
  // Returns false when idx is out of bounds (reported). Records the access when checking is on.
  bool Touch(std::uint32_t idx, Access a) { return (idx < count_ && !check_) || TouchChecked(idx, a); }
  Workgroup* wg_;

 private:
  struct Word {
    std::uint32_t interval = 0xffffffffu;
    std::uint32_t reader[2], writer[2], atomic[2];
    bool raced = false;
  };
  bool TouchChecked(std::uint32_t idx, Access a);
  void Conflict(std::uint32_t idx, Word& w, std::uint32_t inv, Access a);
  std::string name_;
  std::uint32_t count_;
  bool check_;
  std::vector<Word> words_;
  std::vector<std::uint8_t> written_;
};

template <typename T>
class Shared;

// tile[k] inside a phase: reads and writes go through it so the checker sees them.
template <typename T>
class SharedRef {
 public:
  SharedRef(Shared<T>* a, std::uint32_t idx) : a_(a), idx_(idx) {}
  operator T() const { return a_->Load(idx_); }
  SharedRef& operator=(T v) {
    a_->Store(idx_, v);
    return *this;
  }
  SharedRef& operator=(const SharedRef& o) { return *this = static_cast<T>(o); }
  SharedRef& operator+=(T v) { return *this = static_cast<T>(*this + v); }
  SharedRef& operator-=(T v) { return *this = static_cast<T>(*this - v); }
  SharedRef& operator|=(T v) { return *this = static_cast<T>(*this | v); }
  SharedRef& operator&=(T v) { return *this = static_cast<T>(*this & v); }
  Shared<T>* array() const { return a_; }
  std::uint32_t index() const { return idx_; }

 private:
  Shared<T>* a_;
  std::uint32_t idx_;
};

// shared T name[count]; — poisoned: every byte starts as kPoisonByte, and a read of a never-written
// element is reported.
inline constexpr unsigned char kPoisonByte = 0xa5;

template <typename T>
class Shared : public SharedBase {
  static_assert(std::is_trivially_copyable_v<T>, "shared arrays hold plain values");

 public:
  Shared(Workgroup* wg, std::string name, std::uint32_t count) : SharedBase(wg, std::move(name), count) {
    data_.resize(count);
    if (count) std::memset(static_cast<void*>(data_.data()), kPoisonByte, sizeof(T) * count);
  }
  SharedRef<T> operator[](std::uint32_t idx) { return {this, idx}; }
  T Load(std::uint32_t idx) { return Touch(idx, Access::kRead) ? data_[idx] : Poison(); }
  void Store(std::uint32_t idx, T v) {
    if (Touch(idx, Access::kWrite)) data_[idx] = v;
  }
  // Read-modify-write as one atomic access; returns the old value.
  template <typename F>
  T Rmw(std::uint32_t idx, F f) {
    if (!Touch(idx, Access::kAtomic)) return Poison();
    const T old = data_[idx];
    data_[idx] = f(old);
    return old;
  }
  // The array's contents without checking (for tests and for copying out after the last phase).
  const std::vector<T>& raw() const { return data_; }

 private:
  static T Poison() {
    T t;
    std::memset(static_cast<void*>(&t), kPoisonByte, sizeof(T));
    return t;
  }
  std::vector<T> data_;
};

// ---- The workgroup ----------------------------------------------------------------------------------

class Workgroup {
 public:
  Workgroup(const std::string& dispatch, std::uint32_t id, std::uint32_t groups, std::uint32_t local_size,
            std::uint32_t subgroup_size, Schedule schedule, bool check);
  ~Workgroup();
  Workgroup(const Workgroup&) = delete;
  Workgroup& operator=(const Workgroup&) = delete;

  std::uint32_t id() const { return id_; }
  std::uint32_t local_size() const { return local_size_; }
  std::uint32_t subgroup_size() const { return subgroup_size_; }
  std::uint32_t num_subgroups() const { return (local_size_ + subgroup_size_ - 1) / subgroup_size_; }

  // shared T name[count]; declare before the first phase (name is for reports; default "shared#k").
  template <typename T>
  wg::Shared<T>& Shared(std::uint32_t count, std::string name = {}) {
    if (name.empty()) name = "shared#" + std::to_string(shared_.size());
    auto a = std::make_unique<wg::Shared<T>>(this, std::move(name), count);
    auto& ref = *a;
    shared_.push_back(std::move(a));
    return ref;
  }
  template <typename T>
  wg::Private<T> Private(T init = T{}) const { return wg::Private<T>(local_size_, init); }

  // Runs fn(Inv&) for every invocation, one at a time, in the schedule's order.
  template <typename F>
  void Phase(F&& fn) {
    Inv inv = BeginPhase();
    for (std::uint32_t l : order_) {
      current_ = l;
      inv.local_id = l;
      inv.global_id = id_ * local_size_ + l;
      inv.subgroup_id = l / subgroup_size_;
      inv.lane = l % subgroup_size_;
      fn(inv);
    }
    EndPhase();
  }
  // barrier() with memoryBarrierShared(). Between phases: ends the barrier interval. Inside a phase
  // (an invocation-dependent place): counted per invocation and checked when the phase ends.
  void Barrier();

  // Subgroup operations: each is a phase boundary for every subgroup, computed over whole subgroups
  // (lane = local_id % subgroup_size; the last subgroup is partial when L is not a multiple). They do
  // not end the barrier interval (no memory ordering). All lanes are active.
  wg::Private<glm::uvec4> SubgroupBallot(const wg::Private<bool>& pred);
  wg::Private<std::uint32_t> SubgroupAdd(const wg::Private<std::uint32_t>& x);
  wg::Private<std::uint32_t> SubgroupInclusiveAdd(const wg::Private<std::uint32_t>& x);
  wg::Private<std::uint32_t> SubgroupExclusiveAdd(const wg::Private<std::uint32_t>& x);
  wg::Private<bool> SubgroupElect();
  template <typename T>
  wg::Private<T> SubgroupBroadcast(const wg::Private<T>& x, std::uint32_t lane);
  template <typename T>
  wg::Private<T> SubgroupBroadcastFirst(const wg::Private<T>& x) { return SubgroupBroadcast(x, 0); }
  template <typename T>
  wg::Private<T> SubgroupShuffle(const wg::Private<T>& x, const wg::Private<std::uint32_t>& src_lane);
  // subgroupMin, subgroupMax and the like: every lane receives op folded over its subgroup's lanes in
  // lane order (op should be associative and commutative, as the GLSL operations are).
  template <typename T, typename Op>
  wg::Private<T> SubgroupReduce(const wg::Private<T>& x, Op op);

  // Checker internals used by Shared.
  bool checking() const { return check_; }
  std::uint32_t current() const { return current_; }
  std::uint32_t interval() const { return interval_; }
  void AddReport(ReportKind kind, const std::string& array, std::uint32_t word, std::uint32_t a,
                 std::uint32_t b, const std::string& detail);
  std::vector<Report> TakeReports(std::size_t* dropped);

 private:
  bool LaneExists(std::uint32_t subgroup, std::uint32_t lane) const {
    return subgroup * subgroup_size_ + lane < local_size_;
  }
  void SubgroupBoundary();
  void CheckPhaseBarriers();
  Inv BeginPhase();  // sets order_ to this phase's schedule
  void EndPhase();

  std::string dispatch_;
  std::uint32_t id_, groups_, local_size_, subgroup_size_;
  Schedule schedule_;
  bool check_;
  std::uint32_t phase_ = 0, interval_ = 0, current_ = kNoInvocation;
  bool in_phase_ = false;
  std::vector<std::uint32_t> order_;
  std::vector<std::uint32_t> phase_barriers_;  // per invocation, barriers reached inside this phase
  std::vector<std::unique_ptr<SharedBase>> shared_;
  std::vector<Report> reports_;
  std::size_t dropped_ = 0;
};

template <typename T>
wg::Private<T> Workgroup::SubgroupBroadcast(const wg::Private<T>& x, std::uint32_t lane) {
  SubgroupBoundary();
  wg::Private<T> out(local_size_);
  for (std::uint32_t l = 0; l < local_size_; ++l) {
    const std::uint32_t sg = l / subgroup_size_;
    if (lane < subgroup_size_ && LaneExists(sg, lane)) {
      out[l] = x[sg * subgroup_size_ + lane];
    } else if (l % subgroup_size_ == 0) {
      AddReport(ReportKind::kInvalidLane, "", lane, l, kNoInvocation, "broadcast from a missing lane");
    }
  }
  return out;
}

template <typename T>
wg::Private<T> Workgroup::SubgroupShuffle(const wg::Private<T>& x, const wg::Private<std::uint32_t>& src_lane) {
  SubgroupBoundary();
  wg::Private<T> out(local_size_);
  for (std::uint32_t l = 0; l < local_size_; ++l) {
    const std::uint32_t sg = l / subgroup_size_, src = src_lane[l];
    if (src < subgroup_size_ && LaneExists(sg, src)) {
      out[l] = x[sg * subgroup_size_ + src];
    } else {
      AddReport(ReportKind::kInvalidLane, "", src, l, kNoInvocation, "shuffle from a missing lane");
    }
  }
  return out;
}

template <typename T, typename Op>
wg::Private<T> Workgroup::SubgroupReduce(const wg::Private<T>& x, Op op) {
  SubgroupBoundary();
  wg::Private<T> out(local_size_);
  for (std::uint32_t base = 0; base < local_size_; base += subgroup_size_) {
    const std::uint32_t end = std::min(local_size_, base + subgroup_size_);
    T acc = x[base];
    for (std::uint32_t l = base + 1; l < end; ++l) acc = op(acc, x[l]);
    for (std::uint32_t l = base; l < end; ++l) out[l] = acc;
  }
  return out;
}

// ---- Dispatch ---------------------------------------------------------------------------------------

// Runs kernel once per workgroup (workgroups in parallel through ParallelFor). Returns the checker's
// reports (empty when checking is off); throws CheckError instead when options.throw_on_report.
CheckResult Dispatch(const std::string& name, std::uint32_t groups, std::uint32_t local_size,
                     const std::function<void(Workgroup&)>& kernel, const DispatchOptions& options = {});

// ---- Atomics ----------------------------------------------------------------------------------------
// Shared: one atomic access by the current invocation (atomics never race with each other; an atomic
// and a plain access by another invocation in the same barrier interval do). Global: std::atomic_ref,
// sequentially consistent, on words that other workgroups (threads) may update at the same time.
// All return the old value, as GLSL's do.

template <typename T>
concept AtomicWord = std::is_same_v<T, std::uint32_t> || std::is_same_v<T, std::uint64_t>;

template <AtomicWord T>
T AtomicAdd(SharedRef<T> r, T v) { return r.array()->Rmw(r.index(), [v](T o) { return static_cast<T>(o + v); }); }
template <AtomicWord T>
T AtomicMin(SharedRef<T> r, T v) { return r.array()->Rmw(r.index(), [v](T o) { return o < v ? o : v; }); }
template <AtomicWord T>
T AtomicOr(SharedRef<T> r, T v) { return r.array()->Rmw(r.index(), [v](T o) { return static_cast<T>(o | v); }); }

template <AtomicWord T>
T AtomicAnd(SharedRef<T> r, T v) { return r.array()->Rmw(r.index(), [v](T o) { return static_cast<T>(o & v); }); }

template <AtomicWord T>
T AtomicAdd(T& global, T v) { return std::atomic_ref<T>(global).fetch_add(v); }
template <AtomicWord T>
T AtomicOr(T& global, T v) { return std::atomic_ref<T>(global).fetch_or(v); }
template <AtomicWord T>
T AtomicMin(T& global, T v) {
  std::atomic_ref<T> a(global);
  T old = a.load();
  while (v < old && !a.compare_exchange_weak(old, v)) {
  }
  return old;
}

}  // namespace rayspace::wg
