#include "rayspace/sim/executor.h"

#include <spirv/unified1/GLSL.std.450.h>
#include <spirv/unified1/spirv.hpp11>

#include <algorithm>
#include <bitset>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <optional>
#include <random>
#include <type_traits>

#include <fmt/format.h>

#include "device_math.h"
#include "rayspace/sim/grammar.h"
#include "rayspace/sim/shared_check.h"
#include "rayspace/sim/storage_check.h"

namespace rayspace::sim {
namespace {

using Op = spv::Op;

// 0 .. n-1 in the schedule's order; a random order is a permutation drawn from its seed and `salt`.
std::vector<std::uint32_t> ScheduleOrder(std::uint32_t n, const wg::Schedule& s, std::uint64_t salt) {
  std::vector<std::uint32_t> order(n);
  for (std::uint32_t i = 0; i < n; ++i) order[i] = s.order == wg::Order::kReverse ? n - 1 - i : i;
  if (s.order == wg::Order::kRandom) {
    std::mt19937_64 rng(s.seed * 0x2545F4914F6CDD1Dull ^ salt);
    for (std::uint32_t i = n; i > 1; --i) std::swap(order[i - 1], order[rng() % i]);
  }
  return order;
}
constexpr std::uint32_t kNone = ~0u;

// Moves `words` words (register words, or their initcheck shadows, one byte a word): 1 to 4 nearly
// always, as constant-size moves the compiler inlines rather than a call into the C library.
template <class Word>
inline void MoveWords(Word* to, const Word* from, std::size_t words) {
  switch (words * sizeof(Word)) {
    case 1: std::memmove(to, from, 1); return;
    case 2: std::memmove(to, from, 2); return;
    case 4: std::memmove(to, from, 4); return;
    case 8: std::memmove(to, from, 8); return;
    case 12: std::memmove(to, from, 12); return;
    case 16: std::memmove(to, from, 16); return;
    default: std::memmove(to, from, words * sizeof(Word));
  }
}
inline void MoveBytes(void* to, const void* from, std::size_t bytes) {
  MoveWords(static_cast<std::uint8_t*>(to), static_cast<const std::uint8_t*>(from), bytes);
}
// The register words before member or element `index` of a value of `type`, and that part's type.
static std::pair<std::uint32_t, std::uint32_t> Part(const Program& p, std::uint32_t type, std::uint32_t index);

bool IsAtomic(std::uint16_t op) { return op >= static_cast<std::uint16_t>(Op::OpAtomicLoad) && op <= static_cast<std::uint16_t>(Op::OpAtomicXor); }

bool Explicit(std::uint32_t storage) {
  const auto s = static_cast<spv::StorageClass>(storage);
  return s == spv::StorageClass::StorageBuffer || s == spv::StorageClass::Uniform || s == spv::StorageClass::PushConstant;
}

struct Region {
  std::uint8_t* data = nullptr;
  std::size_t bytes = 0;
  std::size_t valid = 0;  // bytes memcheck allows (a binding's own, before its guard words)
};

// kAbsent: a lane of a partial subgroup that no invocation holds.
enum class LaneState : std::uint8_t { kRunning, kBarrier, kDone, kAbsent };

// Lavapipe's min and max (LAVAPIPE.md): the first operand when the second is NaN.
template <class F> F Min(F a, F b) { return b != b ? a : (a < b ? a : b); }
template <class F> F Max(F a, F b) { return b != b ? a : (a > b ? a : b); }

std::uint64_t FloatToU(double x, std::uint32_t width) {
  const double top = width == 64 ? 18446744073709551616.0 : 4294967296.0;
  if (!(x > -1.0) || !(x < top)) return width == 64 ? ~0ull : 0xffffffffull;
  return width == 64 ? static_cast<std::uint64_t>(x) : static_cast<std::uint32_t>(x);
}
std::uint64_t FloatToS(double x, std::uint32_t width) {
  const double top = width == 64 ? 9223372036854775808.0 : 2147483648.0;
  if (!(x >= -top) || !(x < top)) return width == 64 ? 0x8000000000000000ull : 0x80000000ull;
  return width == 64 ? static_cast<std::uint64_t>(static_cast<std::int64_t>(x))
                     : static_cast<std::uint32_t>(static_cast<std::int32_t>(x));
}

std::int64_t SignExtend(std::uint64_t v, std::uint32_t width) {
  return width == 64 ? static_cast<std::int64_t>(v) : static_cast<std::int64_t>(static_cast<std::int32_t>(static_cast<std::uint32_t>(v)));
}
std::uint64_t Mask(std::uint64_t v, std::uint32_t width) { return width == 64 ? v : (v & 0xffffffffull); }

// The scalar component type of a scalar or vector type.
struct Comp {
  TypeKind kind = TypeKind::kNone;
  std::uint32_t width = 32;
  std::uint32_t n = 1;
  std::uint32_t words = 1;  // per component
  const DeviceMath* math = nullptr;  // the worst-conformant device's float arithmetic; null: lavapipe's
};

// The widest subgroup the simulator runs (--subgroup-size 1 to 128).
constexpr std::uint32_t kMaxSubgroup = 128;

class Workgroup {
 public:
  Workgroup(const Program& p, const Dispatch& d, ExecStats& stats, StorageCheck* storage_check)
      : p_(p), d_(d), stats_(stats), storage_check_(storage_check) {
    const std::uint32_t* ls = p.local_size;
    size_ = ls[0] * ls[1] * ls[2];
    sg_ = d.subgroup_size;
    if (size_ == 0 || sg_ == 0) throw SimError(fmt::format("{}: an empty workgroup or subgroup", p.name));
    if (sg_ > kMaxSubgroup) throw SimError(fmt::format("{}: a subgroup of {} invocations (at most {})", p.name, sg_, kMaxSubgroup));
    // Regions: bindings, the push constants, workgroup variables, then per invocation its own.
    for (const Binding& b : d.bindings) regions_.push_back({b.data, b.bytes, b.valid ? std::min(b.valid, b.bytes) : b.bytes});
    push_region_ = static_cast<std::uint32_t>(regions_.size());
    push_copy_.assign(d.push.begin(), d.push.end());
    push_copy_.resize(std::max<std::size_t>(push_copy_.size(), 128), 0);
    regions_.push_back({push_copy_.data(), push_copy_.size(), push_copy_.size()});
    shared_base_ = static_cast<std::uint32_t>(regions_.size());
    std::size_t shared_bytes = 0;
    for (const Variable& v : p.variables)
      if (v.storage == static_cast<std::uint32_t>(spv::StorageClass::Workgroup)) shared_bytes += Pointee(v).words * 4;
    shared_.assign(shared_bytes, 0);
    std::size_t at = 0;
    for (const Variable& v : p.variables)
      if (v.storage == static_cast<std::uint32_t>(spv::StorageClass::Workgroup)) {
        regions_.push_back({shared_.data() + at, Pointee(v).words * 4, Pointee(v).words * 4});
        const auto name = p.names.find(v.id);
        shared_names_.push_back(name == p.names.end() ? fmt::format("%{}", v.id) : name->second);
        at += Pointee(v).words * 4;
      }
    private_base_ = static_cast<std::uint32_t>(regions_.size());
    std::size_t per_lane = 0;
    for (const Variable& v : p.variables)
      if (PerInvocation(v)) {
        private_offsets_.push_back(per_lane);
        private_vars_.push_back(&v);
        per_lane += Pointee(v).words * 4;
      }
    lane_bytes_ = per_lane;
    // Slots: the (subgroup, lane) places, subgroup k's at k*S .. k*S+S-1; a partial layout leaves
    // some empty, at most one in two of a subgroup's.
    slots_cap_ = d.layout.layout == SubgroupLayout::kPartial ? 2 * size_ + sg_ : size_;
    private_.assign(per_lane * slots_cap_, 0);
    for (std::uint32_t l = 0; l < slots_cap_; ++l)
      for (std::size_t k = 0; k < private_vars_.size(); ++k)
        regions_.push_back({private_.data() + l * per_lane + private_offsets_[k], Pointee(*private_vars_[k]).words * 4,
                            Pointee(*private_vars_[k]).words * 4});
    // Constants once a slot for the whole dispatch: nothing writes a constant's registers, and every
    // other register of a lane is written before that lane reads it (SSA dominance, spirv-val), its
    // initcheck state too; a read across lanes (a shuffle) from an inactive lane gives 0 (Subgroup).
    regs_.resize(static_cast<std::size_t>(slots_cap_) * p.reg_words);
    for (std::uint32_t l = 0; l < slots_cap_; ++l)
      std::copy(p.constants.begin(), p.constants.end(), regs_.begin() + static_cast<std::ptrdiff_t>(l) * p.reg_words);
    if (d.checks.On(Checker::kInitcheck)) {
      init_ = true;
      undef_.resize(regs_.size());
      private_undef_.resize(private_.size() / 4);
    }
    if (d.arithmetic.model != DeviceModel::kLavapipe) math_.emplace(d.arithmetic.seed, d.arithmetic.model == DeviceModel::kWorst);
    seg_.resize(slots_cap_);
    prev_.resize(slots_cap_);
    state_.resize(slots_cap_);
    SetUpSlots();
  }

  void Run(const std::uint32_t group[3]) {
    std::fill(shared_.begin(), shared_.end(), 0);
    for (std::uint32_t l = 0; l < slots_cap_; ++l) std::copy(lane_start_.begin(), lane_start_.end(), private_.begin() + l * lane_bytes_);
    group_index_ = group[0] + static_cast<std::uint64_t>(group[1]) * d_.groups[0];
    Layout();
    for (std::uint32_t l = 0; l < slots_; ++l) {
      if (local_of_[l] == kNone) state_[l] = LaneState::kAbsent;
      else StartLane(l, group);
    }
    shared_check_.Begin(shared_.size() / 4, d_.checks);
    group_ = fmt::format("workgroup ({}, {})", group[0], group[1]);
    if (storage_check_) storage_check_->BeginWorkgroup(static_cast<std::uint32_t>(group_index_));
    orders_storage_ = false;
    pending_race_.reset();
    interval_ = 0;
    // The limit is a workgroup's: a dispatch's work grows with its size, a hang is one workgroup's.
    step_end_ = stats_.lane_instructions + std::min<std::uint64_t>(d_.step_limit, ~0ull - stats_.lane_instructions);
    for (;;) {
      for (std::uint32_t s : Order(subgroups_, ++interval_)) RunSubgroup(s * sg_, std::min(slots_, (s + 1) * sg_));
      std::uint32_t waiting = 0, done = 0;
      for (std::uint32_t l = 0; l < slots_; ++l)
        if (state_[l] != LaneState::kAbsent) (state_[l] == LaneState::kBarrier ? waiting : done) += 1;
      if (waiting == 0) break;
      const bool sync = d_.checks.On(Checker::kSynccheck);
      std::uint32_t first = 0;
      while (state_[first] != LaneState::kBarrier) ++first;
      if (done > 0 && sync)
        throw SimError(fmt::format("{}: synccheck: {} invocations wait at a barrier ({}) that {} others, already returned, never reach "
                                   "({}){}",
                                   p_.name, waiting, BarrierAt(seg_[first]), done, group_, Consequence()),
                       Checker::kSynccheck);
      for (std::uint32_t l = 0; l < slots_; ++l) {
        if (state_[l] != LaneState::kBarrier) continue;
        if (sync && seg_[l] != seg_[first])
          throw SimError(fmt::format("{}: synccheck: invocations {} and {} wait at different barriers ({} and {}; {}){}", p_.name,
                                     local_of_[first], local_of_[l],
                                     BarrierAt(seg_[first]), BarrierAt(seg_[l]), group_, Consequence()),
                         Checker::kSynccheck);
        state_[l] = LaneState::kRunning;
      }
      if (pending_race_) throw *pending_race_;
      shared_check_.Barrier();
      if (storage_check_ && orders_storage_) storage_check_->Barrier();
      orders_storage_ = false;
    }
    if (pending_race_) throw *pending_race_;
  }

 private:
  // This workgroup's slots (local_of_, slots_, subgroups_) in the device's subgroup layout, drawn
  // for each workgroup of each dispatch.
  void Layout() {
    const SubgroupLayoutChoice& c = d_.layout;
    local_of_.assign(slots_cap_, kNone);
    if (c.layout == SubgroupLayout::kLinear || (!c.kernel.empty() && c.kernel != p_.name)) {
      for (std::uint32_t i = 0; i < size_; ++i) local_of_[i] = i;
      slots_ = size_;
    } else {
      std::mt19937_64 rng(c.seed * 0xD1B54A32D192ED03ull ^ (d_.dispatch_index << 32) ^ group_index_);
      if (c.layout == SubgroupLayout::kShuffled) {
        for (std::uint32_t i = 0; i < size_; ++i) local_of_[i] = i;
        for (std::uint32_t i = size_; i > 1; --i) std::swap(local_of_[i - 1], local_of_[rng() % i]);
        slots_ = size_;
      } else {
        std::uint32_t next = 0, slot = 0;
        while (next < size_) {
          const std::uint32_t half = (sg_ + 1) / 2;
          const std::uint32_t count = std::min(size_ - next, half + static_cast<std::uint32_t>(rng() % (sg_ - half + 1)));
          std::vector<std::uint32_t> lanes(sg_);
          for (std::uint32_t k = 0; k < sg_; ++k) lanes[k] = k;
          for (std::uint32_t k = sg_; k > 1; --k) std::swap(lanes[k - 1], lanes[rng() % k]);
          std::sort(lanes.begin(), lanes.begin() + count);  // the invocations in local order across the chosen lanes
          for (std::uint32_t k = 0; k < count; ++k) local_of_[slot + lanes[k]] = next++;
          slot += sg_;
        }
        slots_ = slot;
      }
    }
    subgroups_ = (slots_ + sg_ - 1) / sg_;
  }
  // The local invocation index in slot `l`, for reports.
  std::uint32_t Local(std::uint32_t l) const { return local_of_[l]; }

  // The GLSL line of the barrier that ends the segment before `segment` (where a waiting lane resumes).
  std::string BarrierAt(std::uint32_t segment) const { return p_.Where(p_.code[p_.segments[segment - 1].end - 1]); }
  // A race (or a shared word read before any store) found while the barriers were unresolved is the
  // divergence's consequence: said after it.
  std::string Consequence() const { return pending_race_ ? fmt::format("; then, unordered by it: {}", pending_race_->what()) : std::string(); }
  // A race is held until the workgroup's barrier resolves: when it proves divergent, synccheck names
  // the cause; otherwise the race is the finding.
  void Race(const Inst& in, const Finding& f) {
    if (!pending_race_) pending_race_ = Compose(in, f);
  }

  // The subgroups' order in barrier interval `interval` of this workgroup.
  std::vector<std::uint32_t> Order(std::uint32_t n, std::uint64_t interval) const {
    return ScheduleOrder(n, d_.schedule, (d_.dispatch_index * 0x9E3779B97F4A7C15ull) ^ (group_index_ << 20) ^ interval);
  }
  const Type& Pointee(const Variable& v) const { return p_.T(p_.T(v.type).element); }
  static bool PerInvocation(const Variable& v) {
    const auto s = static_cast<spv::StorageClass>(v.storage);
    return s == spv::StorageClass::Input || s == spv::StorageClass::Private || s == spv::StorageClass::Function;
  }
  std::uint32_t* R(std::uint32_t lane, std::uint32_t id) { return regs_.data() + static_cast<std::size_t>(lane) * p_.reg_words + p_.reg[id]; }
  // The subgroup's active lanes (lanes_), by place in the subgroup; Active: `lane` (a slot) among them.
  std::bitset<kMaxSubgroup> ActiveLanes() const {
    std::bitset<kMaxSubgroup> b;
    for (std::uint32_t l : lanes_) b.set(l - sub_first_);
    return b;
  }
  bool Active(const std::bitset<kMaxSubgroup>& active, std::uint32_t lane) const {
    return lane >= sub_first_ && lane - sub_first_ < kMaxSubgroup && active.test(lane - sub_first_);
  }

  // What no workgroup changes, once for the dispatch: every slot's variable pointers, and the memory
  // and initcheck state an invocation's own variables start from (initializers are constants; a
  // Function or Private variable without one holds undefined words).
  void SetUpSlots() {
    lane_start_.assign(lane_bytes_, 0);
    lane_undef_start_.assign(lane_bytes_ / 4, 0);
    std::uint32_t priv = 0;
    for (const Variable& v : p_.variables) {
      if (!PerInvocation(v)) continue;
      const std::size_t at = private_offsets_[priv++];
      const auto s = static_cast<spv::StorageClass>(v.storage);
      if (v.initializer) std::memcpy(lane_start_.data() + at, p_.constants.data() + p_.reg[v.initializer], Pointee(v).words * 4);
      std::fill_n(lane_undef_start_.begin() + static_cast<std::ptrdiff_t>(at / 4), Pointee(v).words,
                  static_cast<std::uint8_t>(s != spv::StorageClass::Input && !v.initializer));
      if (s == spv::StorageClass::Input) inputs_.push_back({&v, at});
    }
    for (std::uint32_t l = 0; l < slots_cap_; ++l) {
      std::uint32_t shared = shared_base_;
      priv = 0;
      for (const Variable& v : p_.variables) {
        std::uint32_t* r = R(l, v.id);
        const auto s = static_cast<spv::StorageClass>(v.storage);
        if (s == spv::StorageClass::StorageBuffer || s == spv::StorageClass::Uniform) {
          if (v.binding >= d_.bindings.size()) throw SimError(fmt::format("{}: binding {} is not bound", p_.name, v.binding));
          r[0] = v.binding;
        } else if (s == spv::StorageClass::PushConstant) {
          r[0] = push_region_;
        } else if (s == spv::StorageClass::Workgroup) {
          r[0] = shared++;
        } else {
          r[0] = private_base_ + l * static_cast<std::uint32_t>(private_vars_.size()) + priv++;
        }
        r[1] = 0;
      }
    }
  }

  void StartLane(std::uint32_t l, const std::uint32_t group[3]) {
    const std::uint32_t* ls = p_.local_size;
    const std::uint32_t li = local_of_[l];
    const std::uint32_t local[3] = {li % ls[0], (li / ls[0]) % ls[1], li / (ls[0] * ls[1])};
    if (init_) std::copy(lane_undef_start_.begin(), lane_undef_start_.end(), private_undef_.begin() + l * (lane_bytes_ / 4));
    for (const auto& [v, at] : inputs_) FillBuiltin(*v, private_.data() + l * lane_bytes_ + at, l, local, group);
    seg_[l] = 0;
    prev_[l] = 0;
    state_[l] = LaneState::kRunning;
  }

  void FillBuiltin(const Variable& v, std::uint8_t* mem, std::uint32_t l, const std::uint32_t local[3], const std::uint32_t group[3]) {
    std::uint32_t w[3] = {0, 0, 0};
    const std::uint32_t* ls = p_.local_size;
    switch (static_cast<spv::BuiltIn>(v.builtin)) {
      case spv::BuiltIn::GlobalInvocationId:
        for (int k = 0; k < 3; ++k) w[k] = group[k] * ls[k] + local[k];
        break;
      case spv::BuiltIn::LocalInvocationId: std::copy(local, local + 3, w); break;
      case spv::BuiltIn::WorkgroupId: std::copy(group, group + 3, w); break;
      case spv::BuiltIn::NumWorkgroups: std::copy(d_.groups, d_.groups + 3, w); break;
      case spv::BuiltIn::WorkgroupSize: std::copy(ls, ls + 3, w); break;
      case spv::BuiltIn::LocalInvocationIndex: w[0] = local_of_[l]; break;
      case spv::BuiltIn::SubgroupSize: w[0] = sg_; break;
      case spv::BuiltIn::SubgroupLocalInvocationId: w[0] = l % sg_; break;
      case spv::BuiltIn::SubgroupId: w[0] = l / sg_; break;
      case spv::BuiltIn::NumSubgroups: w[0] = subgroups_; break;
      default: throw SimError(fmt::format("{}: built-in {} is not simulated", p_.name, NameOf("BuiltIn", v.builtin)));
    }
    std::memcpy(mem, w, std::min<std::size_t>(Pointee(v).words * 4, sizeof w));
  }

  void RunSubgroup(std::uint32_t first, std::uint32_t end) {
    for (;;) {
      std::uint32_t best = kNone;
      for (std::uint32_t l = first; l < end; ++l)
        if (state_[l] == LaneState::kRunning && (best == kNone || p_.segments[seg_[l]].order < p_.segments[best].order)) best = seg_[l];
      if (best == kNone) return;
      lanes_.clear();
      for (std::uint32_t l = first; l < end; ++l)
        if (state_[l] == LaneState::kRunning && seg_[l] == best) lanes_.push_back(l);
      sub_first_ = first;
      sub_end_ = end;
      RunSegment(best);
    }
  }

  [[noreturn]] void Fail(const Inst& in, const std::string& what) const {
    throw SimError(fmt::format("{}: {} ({})", p_.Where(in), what, NameOf("Opcode", in.op)));
  }
  SimError Compose(const Inst& in, const Finding& f) const {
    return SimError(fmt::format("{}: {}: {} ({})", p_.Where(in), CheckerName(f.checker), f.what, NameOf("Opcode", in.op)),
                    f.checker);
  }
  [[noreturn]] void Fail(const Inst& in, const Finding& f) const { throw Compose(in, f); }

  // An integer division by zero: memcheck's finding, or a lenient device's zero.
  std::uint64_t DivisionByZero(const Inst& in) const {
    if (d_.checks.On(Checker::kMemcheck)) Fail(in, Finding{Checker::kMemcheck, "integer division by zero"});
    return 0;
  }

  Comp CompOf(std::uint32_t type) const {
    const Type* t = &p_.T(type);
    Comp c;
    if (t->kind == TypeKind::kVector) {
      c.n = t->count;
      t = &p_.T(t->element);
    }
    c.kind = t->kind;
    c.width = t->kind == TypeKind::kBool ? 32 : t->width;
    c.words = c.width == 64 ? 2 : 1;
    c.math = math_ ? &*math_ : nullptr;
    return c;
  }
  static std::uint64_t Get(const std::uint32_t* p, const Comp& c, std::uint32_t i) {
    return c.words == 2 ? (p[2 * i] | (static_cast<std::uint64_t>(p[2 * i + 1]) << 32)) : p[i];
  }
  static void Put(std::uint32_t* p, const Comp& c, std::uint32_t i, std::uint64_t v) {
    if (c.words == 2) {
      p[2 * i] = static_cast<std::uint32_t>(v);
      p[2 * i + 1] = static_cast<std::uint32_t>(v >> 32);
    } else {
      p[i] = static_cast<std::uint32_t>(v);
    }
  }
  static double F(std::uint64_t bits, const Comp& c) {
    return c.width == 64 ? std::bit_cast<double>(bits) : static_cast<double>(std::bit_cast<float>(static_cast<std::uint32_t>(bits)));
  }
  static std::uint64_t FBits(double v, const Comp& c) {
    return c.width == 64 ? std::bit_cast<std::uint64_t>(v) : std::bit_cast<std::uint32_t>(static_cast<float>(v));
  }

  // A float operation in the component's own precision: float32 values computed as float.
  template <class F32, class F64>
  static std::uint64_t FloatOp(const Comp& c, std::uint64_t a, std::uint64_t b, F32 f32, F64 f64) {
    if (c.width == 64) return std::bit_cast<std::uint64_t>(f64(std::bit_cast<double>(a), std::bit_cast<double>(b)));
    return std::bit_cast<std::uint32_t>(
        f32(std::bit_cast<float>(static_cast<std::uint32_t>(a)), std::bit_cast<float>(static_cast<std::uint32_t>(b))));
  }

  // +, -, *, / in the component's precision, each correctly rounded (lavapipe's), or as the
  // worst-conformant device computes them.
  static std::uint64_t FAdd(const Comp& c, std::uint64_t a, std::uint64_t b) {
    if (c.math) [[unlikely]] return c.math->Binary(FloatOpKind::kAdd, c.width, a, b);
    return FloatOp(c, a, b, [](float x, float y) { return x + y; }, [](double x, double y) { return x + y; });
  }
  static std::uint64_t FSub(const Comp& c, std::uint64_t a, std::uint64_t b) {
    if (c.math) [[unlikely]] return c.math->Binary(FloatOpKind::kSub, c.width, a, b);
    return FloatOp(c, a, b, [](float x, float y) { return x - y; }, [](double x, double y) { return x - y; });
  }
  static std::uint64_t FMul(const Comp& c, std::uint64_t a, std::uint64_t b) {
    if (c.math) [[unlikely]] return c.math->Binary(FloatOpKind::kMul, c.width, a, b);
    return FloatOp(c, a, b, [](float x, float y) { return x * y; }, [](double x, double y) { return x * y; });
  }
  static std::uint64_t FDiv(const Comp& c, std::uint64_t a, std::uint64_t b) {
    if (c.math) [[unlikely]] return c.math->Binary(FloatOpKind::kDiv, c.width, a, b);
    return FloatOp(c, a, b, [](float x, float y) { return x / y; }, [](double x, double y) { return x / y; });
  }

  static std::uint64_t FMin(const Comp& c, std::uint64_t a, std::uint64_t b) {
    if (c.math) [[unlikely]] return c.math->Binary(FloatOpKind::kMin, c.width, a, b);
    return FloatOp(c, a, b, [](float x, float y) { return Min(x, y); }, [](double x, double y) { return Min(x, y); });
  }
  static std::uint64_t FMax(const Comp& c, std::uint64_t a, std::uint64_t b) {
    if (c.math) [[unlikely]] return c.math->Binary(FloatOpKind::kMax, c.width, a, b);
    return FloatOp(c, a, b, [](float x, float y) { return Max(x, y); }, [](double x, double y) { return Max(x, y); });
  }

  template <class Fn>
  void Componentwise(const Inst& in, std::span<const std::uint32_t> ops, std::uint32_t operand_type_of, Fn fn) {
    const Comp rc = CompOf(in.type), oc = CompOf(operand_type_of);
    for (std::uint32_t l : lanes_) {
      std::uint32_t* out = R(l, in.result);
      const std::uint32_t* a = R(l, ops[0]);
      const std::uint32_t* b = ops.size() > 1 ? R(l, ops[1]) : a;
      for (std::uint32_t i = 0; i < rc.n; ++i) Put(out, rc, i, fn(oc, Get(a, oc, i), Get(b, oc, i)));
    }
  }

  // OpCompositeConstruct, Extract and Insert move whole register words. `file(lane, id)` gives a
  // value's first word in the register file or in its definedness shadow (one entry per word, the
  // same layout), so the values and their state move by the same code.
  template <class File>
  void MoveComposite(const Inst& in, File file) {
    const auto ops = p_.Ops(in);
    using Word = std::remove_pointer_t<decltype(file(0u, 0u))>;
    const auto move = [](Word* to, const Word* from, std::uint32_t words) { MoveWords(to, from, words); };
    if (static_cast<Op>(in.op) == Op::OpCompositeConstruct) {
      for (std::uint32_t l : lanes_) {
        std::uint32_t at = 0;
        for (std::uint32_t id : ops) {
          const std::uint32_t n = p_.T(TypeOfValue(id)).words;
          move(file(l, in.result) + at, file(l, id), n);
          at += n;
        }
      }
      return;
    }
    const bool insert = static_cast<Op>(in.op) == Op::OpCompositeInsert;
    const std::uint32_t composite = ops[insert ? 1 : 0];
    std::uint32_t type = TypeOfValue(composite), at = 0;
    for (std::size_t k = insert ? 2 : 1; k < ops.size(); ++k) {
      const auto [w, t] = Part(p_, type, ops[k]);
      at += w;
      type = t;
    }
    const std::uint32_t words = p_.T(type).words, all = p_.T(TypeOfValue(composite)).words;
    for (std::uint32_t l : lanes_) {
      if (insert) {
        move(file(l, in.result), file(l, composite), all);
        move(file(l, in.result) + at, file(l, ops[0]), words);
      } else {
        move(file(l, in.result), file(l, composite) + at, words);
      }
    }
  }

  std::uint32_t TypeOfValue(std::uint32_t id) const { return p_.value_type[id]; }

  void RunSegment(std::uint32_t s) {
    const Segment& seg = p_.segments[s];
    for (std::uint32_t i = seg.first; i < seg.end; ++i) {
      const Inst& in = p_.code[i];
      stats_.lane_instructions += lanes_.size();
      if (stats_.lane_instructions > step_end_) {
        if (pending_race_) throw *pending_race_;
        throw SimError(fmt::format("{}: {} ran more than {} lane-instructions: a hang, or raise the step limit (--step-limit)",
                                   p_.name, group_, d_.step_limit));
      }
      if (d_.coverage) d_.coverage[i] = 1;
      if (init_) TrackBefore(in);
      const bool ended = Execute(in, s);
      if (init_ && in.result && p_.reg[in.result] != kNone) Propagate(in);
      if (ended) return;
    }
  }

  // Returns true when the instruction ended the segment for its lanes (a branch, return or barrier).
  bool Execute(const Inst& in, std::uint32_t s);
  // initcheck on Function and Private values (undef_ shadows each register word, private_undef_ each
  // per-invocation memory word): before an instruction, an undefined value that reaches a branch, an
  // index, an atomic or memory shared with other invocations is a finding, and a store to a
  // per-invocation variable records its words' state; after it, the result's state follows from its
  // operands'.
  void TrackBefore(const Inst& in);
  void Propagate(const Inst& in);
  std::uint8_t* U(std::uint32_t lane, std::uint32_t id) { return undef_.data() + static_cast<std::size_t>(lane) * p_.reg_words + p_.reg[id]; }
  bool Undefined(std::uint32_t lane, std::uint32_t id) {
    if (id >= p_.reg.size() || p_.reg[id] == kNone) return false;
    const std::uint8_t* u = U(lane, id);
    return std::any_of(u, u + p_.T(TypeOfValue(id)).words, [](std::uint8_t b) { return b != 0; });
  }
  // The first word of private_undef_ a pointer of `lane` addresses, or kNone outside per-invocation memory.
  std::size_t PrivateWord(std::uint32_t lane, std::uint32_t ptr_id, std::uint32_t words) {
    const std::uint32_t* p = R(lane, ptr_id);
    if (p[0] < private_base_ || p[0] >= regions_.size() || static_cast<std::size_t>(p[1]) + words * 4u > regions_[p[0]].bytes) return kNone;
    return static_cast<std::size_t>(regions_[p[0]].data - private_.data() + p[1]) / 4;
  }
  void Memory(const Inst& in);
  void Arithmetic(const Inst& in);
  void Extended(const Inst& in);
  void Contracted(const Inst& in);
  void Subgroup(const Inst& in);
  void Atomic(const Inst& in);
  std::uint8_t* Address(const Inst& in, std::uint32_t lane, std::uint32_t ptr_id, std::size_t bytes, AccessKind kind);
  void Copy(const Inst& in, std::uint32_t type, bool expl, std::uint8_t* mem, std::uint32_t* reg, bool load);

  const Program& p_;
  const Dispatch& d_;
  ExecStats& stats_;
  std::uint32_t size_ = 0, sg_ = 0;
  std::uint32_t slots_cap_ = 0, slots_ = 0, subgroups_ = 0;
  std::vector<std::uint32_t> local_of_;  // by slot: the local invocation index it holds (kNone: an absent lane)
  std::vector<Region> regions_;
  std::vector<std::uint8_t> push_copy_, shared_, private_;
  std::uint32_t push_region_ = 0, shared_base_ = 0, private_base_ = 0;
  std::vector<std::size_t> private_offsets_;
  std::vector<const Variable*> private_vars_;
  std::size_t lane_bytes_ = 0;
  std::vector<std::uint8_t> lane_start_, lane_undef_start_;             // a slot's own variables as an invocation starts
  std::vector<std::pair<const Variable*, std::size_t>> inputs_;         // built-in inputs and their offsets in a slot
  std::vector<std::uint32_t> regs_, seg_, prev_;
  std::vector<LaneState> state_;
  std::vector<std::uint32_t> lanes_;
  std::uint64_t step_end_ = 0;  // the lane-instruction count past which this workgroup has hung
  std::uint32_t sub_first_ = 0, sub_end_ = 0;
  SharedCheck shared_check_;
  std::vector<std::uint64_t> scan_;  // a subgroup scan's exclusive values, reused across instructions
  std::uint64_t group_index_ = 0, interval_ = 0;
  std::vector<std::string> shared_names_;  // by shared region, from shared_base_
  std::string group_;
  StorageCheck* storage_check_;  // null when racecheck is off
  bool orders_storage_ = false;  // the barrier being reached orders storage memory (UniformMemory semantics)
  std::vector<std::uint8_t> scratch_;  // what an access outside a binding touches when memcheck is off
  std::optional<SimError> pending_race_;  // the workgroup's first race or unwritten shared read, until its barrier resolves
  bool init_ = false;                  // initcheck on
  std::optional<DeviceMath> math_;     // --device-model worst
  std::vector<std::uint8_t> undef_, private_undef_;
};

void Workgroup::TrackBefore(const Inst& in) {
  const auto ops = p_.Ops(in);
  const auto op = static_cast<Op>(in.op);
  const auto undefined = [&](std::uint32_t l, const char* what) {
    Fail(in, Finding{Checker::kInitcheck, fmt::format("invocation {} of {} {} an undefined value (a Function or Private variable read "
                                                      "before any write on its path, or OpUndef)",
                                                      Local(l), group_, what)});
  };
  switch (op) {
    case Op::OpBranchConditional:
    case Op::OpSwitch:
      for (std::uint32_t l : lanes_)
        if (Undefined(l, ops[0])) undefined(l, "branches on");
      return;
    case Op::OpAccessChain:
    case Op::OpInBoundsAccessChain:
      for (std::uint32_t l : lanes_)
        for (std::size_t k = 1; k < ops.size(); ++k)
          if (Undefined(l, ops[k])) undefined(l, "indexes memory with");
      return;
    case Op::OpStore: {
      const std::uint32_t words = p_.T(TypeOfValue(ops[1])).words;
      for (std::uint32_t l : lanes_) {
        const std::size_t w = PrivateWord(l, ops[0], words);
        if (w != kNone) {
          MoveBytes(private_undef_.data() + w, U(l, ops[1]), words);
        } else if (Undefined(l, ops[1])) {
          undefined(l, "stores to memory other invocations see");
        }
      }
      return;
    }
    default:
      // The atomics' value operands (after pointer, scope and semantics); OpAtomicLoad has none.
      if (IsAtomic(in.op))
        for (std::uint32_t l : lanes_)
          for (std::size_t k = 3; k < ops.size(); ++k)
            if (Undefined(l, ops[k])) undefined(l, "gives an atomic operation");
      return;
  }
}

// Long: one case per way a result takes its operands' definedness; apart they would hide the one rule.
void Workgroup::Propagate(const Inst& in) {
  const auto ops = p_.Ops(in);
  const auto op = static_cast<Op>(in.op);
  const std::uint32_t words = p_.T(in.type).words;
  const auto copy = [&](std::uint32_t l, std::uint32_t from, std::uint32_t at = 0) { MoveBytes(U(l, in.result), U(l, from) + at, words); };
  const auto set = [&](std::uint32_t l, bool u) { std::fill_n(U(l, in.result), words, static_cast<std::uint8_t>(u)); };
  switch (op) {
    case Op::OpLoad:
      for (std::uint32_t l : lanes_) {
        const std::size_t w = PrivateWord(l, ops[0], words);
        if (w != kNone) MoveBytes(U(l, in.result), private_undef_.data() + w, words);
        else set(l, false);  // shared memory has its own initcheck; storage buffers are the host's
      }
      return;
    case Op::OpUndef:
      for (std::uint32_t l : lanes_) set(l, true);
      return;
    case Op::OpPhi:
      for (std::uint32_t l : lanes_)
        for (std::size_t k = 0; k + 1 < ops.size(); k += 2)
          if (ops[k + 1] == prev_[l]) {
            copy(l, ops[k]);
            break;
          }
      return;
    case Op::OpCopyObject:
    case Op::OpCopyLogical:
    case Op::OpBitcast:
      for (std::uint32_t l : lanes_) copy(l, ops[0]);
      return;
    case Op::OpSelect: {
      const bool scalar = CompOf(TypeOfValue(ops[0])).n == 1;
      for (std::uint32_t l : lanes_) {
        if (scalar && !Undefined(l, ops[0])) copy(l, R(l, ops[0])[0] ? ops[1] : ops[2]);
        else set(l, Undefined(l, ops[0]) || Undefined(l, ops[1]) || Undefined(l, ops[2]));
      }
      return;
    }
    case Op::OpCompositeConstruct:
    case Op::OpCompositeExtract:
    case Op::OpCompositeInsert: MoveComposite(in, [this](std::uint32_t l, std::uint32_t id) { return U(l, id); }); return;
    case Op::OpVectorShuffle:
      for (std::uint32_t l : lanes_) set(l, Undefined(l, ops[0]) || Undefined(l, ops[1]));
      return;
    case Op::OpExtInst:
      for (std::uint32_t l : lanes_) {
        bool u = false;
        for (std::size_t k = 2; k < ops.size(); ++k) u = u || Undefined(l, ops[k]);
        set(l, u);
      }
      return;
    case Op::OpAccessChain:
    case Op::OpInBoundsAccessChain:
    case Op::OpArrayLength:
      for (std::uint32_t l : lanes_) set(l, false);
      return;
    default: break;
  }
  if (IsAtomic(in.op)) {
    for (std::uint32_t l : lanes_) set(l, false);  // what memory held
    return;
  }
  if (op == Op::OpGroupNonUniformShuffle || op == Op::OpGroupNonUniformBroadcast || op == Op::OpGroupNonUniformBroadcastFirst) {
    // Each lane's result is one lane's value: undefined when that lane's is, or when it is inactive.
    const std::bitset<kMaxSubgroup> active = ActiveLanes();
    for (std::uint32_t l : lanes_) {
      if (op != Op::OpGroupNonUniformBroadcastFirst && Undefined(l, ops[2])) {
        set(l, true);
        continue;
      }
      const std::uint32_t src = op == Op::OpGroupNonUniformBroadcastFirst ? lanes_[0] : sub_first_ + R(l, ops[2])[0];
      if (Active(active, src)) MoveBytes(U(l, in.result), U(src, ops[1]), words);
      else set(l, true);
    }
    return;
  }
  if (in.op >= static_cast<std::uint16_t>(Op::OpGroupNonUniformElect) && in.op <= static_cast<std::uint16_t>(Op::OpGroupNonUniformQuadSwap)) {
    // A subgroup operation mixes the active lanes' values: undefined for all when any lane's is. The
    // arithmetic and ballot-count forms have a literal group operation as their second operand.
    const bool literal = ops.size() > 2 && (op == Op::OpGroupNonUniformBallotBitCount ||
                                            (in.op >= static_cast<std::uint16_t>(Op::OpGroupNonUniformIAdd) &&
                                             in.op <= static_cast<std::uint16_t>(Op::OpGroupNonUniformLogicalXor)));
    bool u = false;
    for (std::uint32_t l : lanes_)
      for (std::size_t k = literal ? 2 : 1; k < ops.size(); ++k) u = u || Undefined(l, ops[k]);
    for (std::uint32_t l : lanes_) set(l, u);
    return;
  }
  // Arithmetic, comparisons, conversions: undefined when any operand is.
  for (std::uint32_t l : lanes_) {
    bool u = false;
    for (std::uint32_t id : ops) u = u || Undefined(l, id);
    set(l, u);
  }
}

// Long: the dispatch over opcodes, one case each.
bool Workgroup::Execute(const Inst& in, std::uint32_t s) {
  const auto ops = p_.Ops(in);
  const std::uint32_t label = p_.segments[s].label;
  const auto jump = [&](std::uint32_t l, std::uint32_t target) {
    prev_[l] = label;
    seg_[l] = p_.segment_of_label[target];
    if (seg_[l] == kNone) [[unlikely]] Fail(in, "a branch to no block of the entry function");
  };
  switch (static_cast<Op>(in.op)) {
    case Op::OpNop:
    case Op::OpSelectionMerge:
    case Op::OpLoopMerge:
    case Op::OpUndef: return false;
    case Op::OpMemoryBarrier:
      if (R(lanes_[0], ops[1])[0] & static_cast<std::uint32_t>(spv::MemorySemanticsMask::UniformMemory)) orders_storage_ = true;
      return false;
    case Op::OpBranch:
      for (std::uint32_t l : lanes_) jump(l, ops[0]);
      return true;
    case Op::OpBranchConditional:
      for (std::uint32_t l : lanes_) jump(l, R(l, ops[0])[0] ? ops[1] : ops[2]);
      return true;
    case Op::OpSwitch: {
      const Comp c = CompOf(TypeOfValue(ops[0]));
      for (std::uint32_t l : lanes_) {
        const std::uint64_t v = Get(R(l, ops[0]), c, 0);
        std::uint32_t target = ops[1];
        for (std::size_t k = 2; k + c.words < ops.size(); k += c.words + 1) {
          const std::uint64_t lit = c.words == 2 ? (ops[k] | (static_cast<std::uint64_t>(ops[k + 1]) << 32)) : ops[k];
          if (lit == v) {
            target = ops[k + c.words];
            break;
          }
        }
        jump(l, target);
      }
      return true;
    }
    case Op::OpReturn:
    case Op::OpReturnValue:
      for (std::uint32_t l : lanes_) state_[l] = LaneState::kDone;
      return true;
    case Op::OpControlBarrier: {
      // A barrier in non-uniform control flow: lanes of this subgroup still running elsewhere.
      std::uint32_t running = 0;
      for (std::uint32_t l = sub_first_; l < sub_end_; ++l) running += state_[l] == LaneState::kRunning;
      if (running != lanes_.size() && d_.checks.On(Checker::kSynccheck))
        Fail(in, Finding{Checker::kSynccheck, fmt::format("a barrier reached by {} of the {} running invocations of subgroup {} (non-uniform "
                                                          "control flow, {})",
                                                          lanes_.size(), running, sub_first_ / sg_, group_)});
      if (R(lanes_[0], ops[2])[0] & static_cast<std::uint32_t>(spv::MemorySemanticsMask::UniformMemory)) orders_storage_ = true;
      for (std::uint32_t l : lanes_) {
        state_[l] = LaneState::kBarrier;
        seg_[l] = s + 1;
      }
      return true;
    }
    case Op::OpUnreachable:
    case Op::OpKill: Fail(in, "reached");
    case Op::OpPhi: {
      const std::uint32_t words = p_.T(in.type).words;
      for (std::uint32_t l : lanes_) {
        bool found = false;
        for (std::size_t k = 0; k + 1 < ops.size(); k += 2)
          if (ops[k + 1] == prev_[l]) {
            MoveWords(R(l, in.result), R(l, ops[k]), words);
            found = true;
            break;
          }
        if (!found) Fail(in, "no incoming value for the block the invocation came from");
      }
      return false;
    }
    case Op::OpLoad:
    case Op::OpStore:
    case Op::OpAccessChain:
    case Op::OpInBoundsAccessChain:
    case Op::OpArrayLength:
    case Op::OpCopyObject:
    case Op::OpCopyLogical: Memory(in); return false;
    case Op::OpAtomicLoad:
    case Op::OpAtomicStore:
    case Op::OpAtomicExchange:
    case Op::OpAtomicCompareExchange:
    case Op::OpAtomicIAdd:
    case Op::OpAtomicISub:
    case Op::OpAtomicUMin:
    case Op::OpAtomicUMax:
    case Op::OpAtomicSMin:
    case Op::OpAtomicSMax:
    case Op::OpAtomicAnd:
    case Op::OpAtomicOr:
    case Op::OpAtomicXor: Atomic(in); return false;
    case Op::OpGroupNonUniformElect:
    case Op::OpGroupNonUniformAll:
    case Op::OpGroupNonUniformAny:
    case Op::OpGroupNonUniformBroadcast:
    case Op::OpGroupNonUniformBroadcastFirst:
    case Op::OpGroupNonUniformBallot:
    case Op::OpGroupNonUniformBallotBitCount:
    case Op::OpGroupNonUniformBallotFindLSB:
    case Op::OpGroupNonUniformBallotFindMSB:
    case Op::OpGroupNonUniformShuffle:
    case Op::OpGroupNonUniformIAdd:
    case Op::OpGroupNonUniformUMin:
    case Op::OpGroupNonUniformUMax:
    case Op::OpGroupNonUniformFMin:
    case Op::OpGroupNonUniformFMax: Subgroup(in); return false;
    case Op::OpExtInst: Extended(in); return false;
    default: Arithmetic(in); return false;
  }
}

std::uint8_t* Workgroup::Address(const Inst& in, std::uint32_t lane, std::uint32_t ptr_id, std::size_t bytes, AccessKind kind) {
  const std::uint32_t* p = R(lane, ptr_id);
  if (p[0] >= regions_.size()) Fail(in, "memcheck: a pointer to no memory");
  const Region& r = regions_[p[0]];
  const std::size_t end = static_cast<std::size_t>(p[1]) + bytes;
  if (end > r.valid && d_.checks.On(Checker::kMemcheck)) {
    const bool binding = p[0] < d_.bindings.size();
    Fail(in, Finding{Checker::kMemcheck, fmt::format("an access of {} bytes at byte {} of a {}-byte {}{} (invocation {} of {})", bytes, p[1],
                                                     r.valid, binding ? fmt::format("binding {}", p[0]) : std::string("variable"),
                                                     end <= r.bytes ? ", into the guard words after its end" : "", Local(lane), group_)});
  }
  if (end > r.bytes) {  // a lenient device: the read gives zero, the write lands nowhere
    scratch_.assign(bytes, 0);
    return scratch_.data();
  }
  if (p[0] >= shared_base_ && p[0] < private_base_) {
    const std::size_t base = static_cast<std::size_t>(r.data - shared_.data()) / 4;
    for (std::size_t w = p[1] / 4; w < (p[1] + bytes + 3) / 4; ++w)
      if (auto finding = shared_check_.Access(base + w, Local(lane), kind)) {
        finding->what += fmt::format(" (shared '{}' word {}, {})", shared_names_[p[0] - shared_base_], w, group_);
        Race(in, *finding);  // an unwritten word read may be a store this interval has yet to make: a race too
      }
  } else if (storage_check_ && p[0] < d_.bindings.size()) {
    for (std::size_t w = p[1] / 4; w < (p[1] + bytes + 3) / 4; ++w)
      if (auto finding = storage_check_->Access(p[0], w, Local(lane), kind)) Race(in, *finding);
  }
  return r.data + p[1];
}

// Copies a value between memory and its register words: explicit layouts (storage buffers, push
// constants) by their Offset, ArrayStride and MatrixStride; the others packed as in registers.
void Workgroup::Copy(const Inst& in, std::uint32_t type, bool expl, std::uint8_t* mem, std::uint32_t* reg, bool load) {
  const Type& t = p_.T(type);
  const auto move = [&](std::uint8_t* m, std::uint32_t* r, std::size_t words) {
    if (load) MoveBytes(r, m, words * 4);
    else MoveBytes(m, r, words * 4);
  };
  if (!expl || t.kind == TypeKind::kInt || t.kind == TypeKind::kFloat || t.kind == TypeKind::kBool || t.kind == TypeKind::kPointer) {
    move(mem, reg, t.words);
    return;
  }
  switch (t.kind) {
    case TypeKind::kVector: move(mem, reg, t.words); return;  // std430 and scalar layouts pack vectors
    case TypeKind::kMatrix:
    case TypeKind::kArray: {
      const std::uint32_t ew = p_.T(t.element).words;
      const std::uint32_t stride = t.stride ? t.stride : ew * 4;
      for (std::uint32_t i = 0; i < t.count; ++i) Copy(in, t.element, expl, mem + static_cast<std::size_t>(i) * stride, reg + i * ew, load);
      return;
    }
    case TypeKind::kStruct: {
      std::uint32_t w = 0;
      for (std::size_t m = 0; m < t.members.size(); ++m) {
        Copy(in, t.members[m], expl, mem + t.offsets[m], reg + w, load);
        w += p_.T(t.members[m]).words;
      }
      return;
    }
    default: Fail(in, "a value of this type cannot be loaded or stored");
  }
}

// The byte size of a value of `type` in memory of the given layout (the extent its accesses touch).
static std::size_t Extent(const Program& p, std::uint32_t type, bool expl) {
  const Type& t = p.T(type);
  if (!expl) return t.words * 4;
  switch (t.kind) {
    case TypeKind::kMatrix:
    case TypeKind::kArray:
      return t.count == 0 ? 0 : static_cast<std::size_t>(t.count - 1) * (t.stride ? t.stride : p.T(t.element).words * 4) + Extent(p, t.element, expl);
    case TypeKind::kStruct: {
      std::size_t e = 0;
      for (std::size_t m = 0; m < t.members.size(); ++m) e = std::max(e, t.offsets[m] + Extent(p, t.members[m], expl));
      return e;
    }
    default: return t.words * 4;
  }
}

void Workgroup::Memory(const Inst& in) {
  const auto ops = p_.Ops(in);
  switch (static_cast<Op>(in.op)) {
    case Op::OpLoad: {
      const Type& pt = p_.T(TypeOfValue(ops[0]));
      const bool expl = Explicit(pt.storage);
      const std::size_t bytes = Extent(p_, in.type, expl);
      for (std::uint32_t l : lanes_) Copy(in, in.type, expl, Address(in, l, ops[0], bytes, AccessKind::kRead), R(l, in.result), true);
      return;
    }
    case Op::OpStore: {
      const Type& pt = p_.T(TypeOfValue(ops[0]));
      const bool expl = Explicit(pt.storage);
      const std::size_t bytes = Extent(p_, pt.element, expl);
      for (std::uint32_t l : lanes_) Copy(in, pt.element, expl, Address(in, l, ops[0], bytes, AccessKind::kWrite), R(l, ops[1]), false);
      return;
    }
    case Op::OpAccessChain:
    case Op::OpInBoundsAccessChain: {
      const Type& base = p_.T(TypeOfValue(ops[0]));
      const bool expl = Explicit(base.storage);
      for (std::uint32_t l : lanes_) {
        std::uint32_t type = base.element;
        std::int64_t off = R(l, ops[0])[1];
        for (std::size_t k = 1; k < ops.size(); ++k) {
          const Type& t = p_.T(type);
          const Comp ic = CompOf(TypeOfValue(ops[k]));
          const std::int64_t idx = SignExtend(Get(R(l, ops[k]), ic, 0), ic.width);
          if (t.kind == TypeKind::kStruct) {
            if (expl) {
              off += t.offsets.at(static_cast<std::size_t>(idx));
            } else {
              for (std::int64_t m = 0; m < idx; ++m) off += p_.T(t.members[static_cast<std::size_t>(m)]).words * 4;
            }
            type = t.members.at(static_cast<std::size_t>(idx));
          } else {
            const std::uint32_t ew = p_.T(t.element).words;
            const std::uint32_t stride =
                t.kind == TypeKind::kVector ? p_.T(t.element).words * 4 : (expl && t.stride ? t.stride : ew * 4);
            off += idx * static_cast<std::int64_t>(stride);
            type = t.element;
          }
        }
        std::uint32_t* out = R(l, in.result);
        out[0] = R(l, ops[0])[0];
        out[1] = off < 0 || off > 0xffffffffll ? 0xffffffffu : static_cast<std::uint32_t>(off);
      }
      return;
    }
    case Op::OpArrayLength: {
      const Type& st = p_.T(p_.T(TypeOfValue(ops[0])).element);
      const std::uint32_t member = ops[1];
      const Type& arr = p_.T(st.members.at(member));
      for (std::uint32_t l : lanes_) {
        const std::uint32_t* ptr = R(l, ops[0]);
        if (ptr[0] >= regions_.size()) Fail(in, "a pointer to no memory");
        const std::size_t bytes = regions_[ptr[0]].bytes, start = ptr[1] + st.offsets[member];
        R(l, in.result)[0] = bytes > start && arr.stride ? static_cast<std::uint32_t>((bytes - start) / arr.stride) : 0;
      }
      return;
    }
    default: {  // OpCopyObject, OpCopyLogical: the same register words
      const std::uint32_t words = p_.T(in.type).words;
      for (std::uint32_t l : lanes_) MoveWords(R(l, in.result), R(l, ops[0]), words);
      return;
    }
  }
}

// The register-word offset of member or element `index` of a composite type, and its type.
static std::pair<std::uint32_t, std::uint32_t> Part(const Program& p, std::uint32_t type, std::uint32_t index) {
  const Type& t = p.T(type);
  if (t.kind == TypeKind::kStruct) {
    std::uint32_t w = 0;
    for (std::uint32_t m = 0; m < index; ++m) w += p.T(t.members[m]).words;
    return {w, t.members.at(index)};
  }
  return {index * p.T(t.element).words, t.element};
}

// Long: one case per arithmetic opcode, each a line or two.
void Workgroup::Arithmetic(const Inst& in) {
  const auto ops = p_.Ops(in);
  const auto op = static_cast<Op>(in.op);
  switch (op) {
    case Op::OpIAdd: Componentwise(in, ops, in.type, [](const Comp& c, std::uint64_t a, std::uint64_t b) { return Mask(a + b, c.width); }); return;
    case Op::OpISub: Componentwise(in, ops, in.type, [](const Comp& c, std::uint64_t a, std::uint64_t b) { return Mask(a - b, c.width); }); return;
    case Op::OpIMul: Componentwise(in, ops, in.type, [](const Comp& c, std::uint64_t a, std::uint64_t b) { return Mask(a * b, c.width); }); return;
    case Op::OpSNegate: Componentwise(in, ops, in.type, [](const Comp& c, std::uint64_t a, std::uint64_t) { return Mask(0 - a, c.width); }); return;
    case Op::OpUDiv:
    case Op::OpUMod:
      Componentwise(in, ops, in.type, [&](const Comp&, std::uint64_t a, std::uint64_t b) {
        if (b == 0) return DivisionByZero(in);
        return op == Op::OpUDiv ? a / b : a % b;
      });
      return;
    case Op::OpSDiv:
    case Op::OpSRem:
    case Op::OpSMod:
      Componentwise(in, ops, in.type, [&](const Comp& c, std::uint64_t ua, std::uint64_t ub) {
        const std::int64_t a = SignExtend(ua, c.width), b = SignExtend(ub, c.width);
        if (b == 0) return DivisionByZero(in);
        if (b == -1) return op == Op::OpSDiv ? Mask(0 - ua, c.width) : std::uint64_t{0};
        std::int64_t r = op == Op::OpSDiv ? a / b : a % b;
        if (op == Op::OpSMod && r != 0 && ((r < 0) != (b < 0))) r += b;
        return Mask(static_cast<std::uint64_t>(r), c.width);
      });
      return;
    case Op::OpShiftLeftLogical:
    case Op::OpShiftRightLogical:
    case Op::OpShiftRightArithmetic: {
      const Comp rc = CompOf(in.type), sc = CompOf(TypeOfValue(ops[1]));
      for (std::uint32_t l : lanes_) {
        const std::uint32_t *a = R(l, ops[0]), *b = R(l, ops[1]);
        for (std::uint32_t i = 0; i < rc.n; ++i) {
          const std::uint64_t v = Get(a, rc, i), n = Get(b, sc, i);
          if (n >= rc.width) {
            if (d_.checks.On(Checker::kMemcheck))
              Fail(in, Finding{Checker::kMemcheck, fmt::format("a shift by {}, at least the width {}", n, rc.width)});
            Put(R(l, in.result), rc, i, 0);  // undefined: a lenient device's zero
            continue;
          }
          std::uint64_t r = op == Op::OpShiftLeftLogical ? v << n
                            : op == Op::OpShiftRightLogical ? v >> n
                                                             : static_cast<std::uint64_t>(SignExtend(v, rc.width) >> n);
          Put(R(l, in.result), rc, i, Mask(r, rc.width));
        }
      }
      return;
    }
    case Op::OpBitwiseAnd: Componentwise(in, ops, in.type, [](const Comp&, std::uint64_t a, std::uint64_t b) { return a & b; }); return;
    case Op::OpBitwiseOr: Componentwise(in, ops, in.type, [](const Comp&, std::uint64_t a, std::uint64_t b) { return a | b; }); return;
    case Op::OpBitwiseXor: Componentwise(in, ops, in.type, [](const Comp&, std::uint64_t a, std::uint64_t b) { return a ^ b; }); return;
    case Op::OpNot: Componentwise(in, ops, in.type, [](const Comp& c, std::uint64_t a, std::uint64_t) { return Mask(~a, c.width); }); return;
    case Op::OpBitCount:
      Componentwise(in, ops, TypeOfValue(ops[0]), [](const Comp&, std::uint64_t a, std::uint64_t) { return static_cast<std::uint64_t>(std::popcount(a)); });
      return;
    case Op::OpBitFieldUExtract:
    case Op::OpBitFieldInsert: {
      const Comp rc = CompOf(in.type);
      const bool insert = op == Op::OpBitFieldInsert;
      const std::uint32_t off_id = ops[insert ? 2 : 1], count_id = ops[insert ? 3 : 2];
      const Comp oc = CompOf(TypeOfValue(off_id));
      for (std::uint32_t l : lanes_) {
        const std::uint64_t off = Get(R(l, off_id), oc, 0), count = Get(R(l, count_id), oc, 0);
        if (off + count > rc.width) Fail(in, "a bit field beyond the width");
        const std::uint64_t mask = count >= 64 ? ~0ull : ((1ull << count) - 1);
        for (std::uint32_t i = 0; i < rc.n; ++i) {
          const std::uint64_t base = Get(R(l, ops[0]), rc, i);
          const std::uint64_t r = insert ? (base & ~(mask << off)) | ((Get(R(l, ops[1]), rc, i) & mask) << off) : (base >> off) & mask;
          Put(R(l, in.result), rc, i, Mask(r, rc.width));
        }
      }
      return;
    }
    case Op::OpFAdd:
    case Op::OpFSub:
      if (math_ && p_.contract[&in - p_.code.data()] != kNoContraction) {
        Contracted(in);
        return;
      }
      Componentwise(in, ops, in.type, op == Op::OpFAdd ? FAdd : FSub);
      return;
    case Op::OpFMul: Componentwise(in, ops, in.type, FMul); return;
    case Op::OpFDiv: Componentwise(in, ops, in.type, FDiv); return;
    case Op::OpFNegate: Componentwise(in, ops, in.type, [](const Comp& c, std::uint64_t a, std::uint64_t) { return a ^ (c.width == 64 ? 0x8000000000000000ull : 0x80000000ull); }); return;
    case Op::OpVectorTimesScalar: {
      const Comp c = CompOf(in.type);
      for (std::uint32_t l : lanes_) {
        const std::uint64_t s = Get(R(l, ops[1]), c, 0);
        for (std::uint32_t i = 0; i < c.n; ++i)
          Put(R(l, in.result), c, i, FMul(c, Get(R(l, ops[0]), c, i), s));
      }
      return;
    }
    case Op::OpDot: {
      const Comp c = CompOf(TypeOfValue(ops[0]));
      for (std::uint32_t l : lanes_) {
        std::uint64_t sum = 0;
        for (std::uint32_t i = 0; i < c.n; ++i) {
          const std::uint64_t prod = FMul(c, Get(R(l, ops[0]), c, i), Get(R(l, ops[1]), c, i));
          sum = i == 0 ? prod : FAdd(c, sum, prod);
        }
        Put(R(l, in.result), c, 0, sum);
      }
      return;
    }
    case Op::OpIEqual:
    case Op::OpINotEqual:
    case Op::OpUGreaterThan:
    case Op::OpSGreaterThan:
    case Op::OpUGreaterThanEqual:
    case Op::OpSGreaterThanEqual:
    case Op::OpULessThan:
    case Op::OpSLessThan:
    case Op::OpULessThanEqual:
    case Op::OpSLessThanEqual:
    case Op::OpLogicalEqual:
    case Op::OpLogicalNotEqual:
      Componentwise(in, ops, TypeOfValue(ops[0]), [op](const Comp& c, std::uint64_t ua, std::uint64_t ub) -> std::uint64_t {
        const std::int64_t a = SignExtend(ua, c.width), b = SignExtend(ub, c.width);
        switch (op) {
          case Op::OpIEqual:
          case Op::OpLogicalEqual: return ua == ub;
          case Op::OpINotEqual:
          case Op::OpLogicalNotEqual: return ua != ub;
          case Op::OpUGreaterThan: return ua > ub;
          case Op::OpSGreaterThan: return a > b;
          case Op::OpUGreaterThanEqual: return ua >= ub;
          case Op::OpSGreaterThanEqual: return a >= b;
          case Op::OpULessThan: return ua < ub;
          case Op::OpSLessThan: return a < b;
          case Op::OpULessThanEqual: return ua <= ub;
          default: return a <= b;
        }
      });
      return;
    case Op::OpFOrdEqual:
    case Op::OpFUnordEqual:
    case Op::OpFOrdNotEqual:
    case Op::OpFUnordNotEqual:
    case Op::OpFOrdLessThan:
    case Op::OpFUnordLessThan:
    case Op::OpFOrdGreaterThan:
    case Op::OpFUnordGreaterThan:
    case Op::OpFOrdLessThanEqual:
    case Op::OpFUnordLessThanEqual:
    case Op::OpFOrdGreaterThanEqual:
    case Op::OpFUnordGreaterThanEqual:
      Componentwise(in, ops, TypeOfValue(ops[0]), [op](const Comp& c, std::uint64_t ua, std::uint64_t ub) -> std::uint64_t {
        const double a = F(ua, c), b = F(ub, c);
        const bool unordered = a != a || b != b;
        switch (op) {
          case Op::OpFOrdEqual: return !unordered && a == b;
          case Op::OpFUnordEqual: return unordered || a == b;
          case Op::OpFOrdNotEqual: return !unordered && a != b;
          case Op::OpFUnordNotEqual: return unordered || a != b;
          case Op::OpFOrdLessThan: return !unordered && a < b;
          case Op::OpFUnordLessThan: return unordered || a < b;
          case Op::OpFOrdGreaterThan: return !unordered && a > b;
          case Op::OpFUnordGreaterThan: return unordered || a > b;
          case Op::OpFOrdLessThanEqual: return !unordered && a <= b;
          case Op::OpFUnordLessThanEqual: return unordered || a <= b;
          case Op::OpFOrdGreaterThanEqual: return !unordered && a >= b;
          default: return unordered || a >= b;
        }
      });
      return;
    case Op::OpLogicalOr: Componentwise(in, ops, in.type, [](const Comp&, std::uint64_t a, std::uint64_t b) -> std::uint64_t { return a || b; }); return;
    case Op::OpLogicalAnd: Componentwise(in, ops, in.type, [](const Comp&, std::uint64_t a, std::uint64_t b) -> std::uint64_t { return a && b; }); return;
    case Op::OpLogicalNot: Componentwise(in, ops, in.type, [](const Comp&, std::uint64_t a, std::uint64_t) -> std::uint64_t { return !a; }); return;
    case Op::OpIsNan: Componentwise(in, ops, TypeOfValue(ops[0]), [](const Comp& c, std::uint64_t a, std::uint64_t) -> std::uint64_t { return std::isnan(F(a, c)); }); return;
    case Op::OpIsInf: Componentwise(in, ops, TypeOfValue(ops[0]), [](const Comp& c, std::uint64_t a, std::uint64_t) -> std::uint64_t { return std::isinf(F(a, c)); }); return;
    case Op::OpAny:
    case Op::OpAll: {
      const Comp c = CompOf(TypeOfValue(ops[0]));
      for (std::uint32_t l : lanes_) {
        bool any = false, all = true;
        for (std::uint32_t i = 0; i < c.n; ++i) {
          any |= Get(R(l, ops[0]), c, i) != 0;
          all &= Get(R(l, ops[0]), c, i) != 0;
        }
        R(l, in.result)[0] = op == Op::OpAny ? any : all;
      }
      return;
    }
    case Op::OpSelect: {
      const Comp cc = CompOf(TypeOfValue(ops[0]));
      const std::uint32_t words = p_.T(in.type).words;
      if (cc.n == 1) {
        for (std::uint32_t l : lanes_) MoveWords(R(l, in.result), R(l, R(l, ops[0])[0] ? ops[1] : ops[2]), words);
      } else {
        const Comp rc = CompOf(in.type);
        for (std::uint32_t l : lanes_)
          for (std::uint32_t i = 0; i < rc.n; ++i) Put(R(l, in.result), rc, i, Get(R(l, Get(R(l, ops[0]), cc, i) ? ops[1] : ops[2]), rc, i));
      }
      return;
    }
    case Op::OpConvertFToU:
    case Op::OpConvertFToS:
    case Op::OpConvertSToF:
    case Op::OpConvertUToF:
    case Op::OpUConvert:
    case Op::OpSConvert:
    case Op::OpFConvert: {
      const Comp rc = CompOf(in.type), oc = CompOf(TypeOfValue(ops[0]));
      for (std::uint32_t l : lanes_)
        for (std::uint32_t i = 0; i < rc.n; ++i) {
          const std::uint64_t v = Get(R(l, ops[0]), oc, i);
          std::uint64_t r = 0;
          switch (op) {
            case Op::OpConvertFToU: r = FloatToU(F(v, oc), rc.width); break;
            case Op::OpConvertFToS: r = FloatToS(F(v, oc), rc.width); break;
            case Op::OpConvertSToF:
              if (rc.math) {
                const std::int64_t sv = SignExtend(v, oc.width);
                r = rc.math->FromInteger(rc.width, sv < 0 ? 0 - static_cast<std::uint64_t>(sv) : static_cast<std::uint64_t>(sv), sv < 0);
                break;
              }
              r = rc.width == 64 ? std::bit_cast<std::uint64_t>(static_cast<double>(SignExtend(v, oc.width)))
                                 : std::bit_cast<std::uint32_t>(static_cast<float>(SignExtend(v, oc.width)));
              break;
            case Op::OpConvertUToF:
              if (rc.math) {
                r = rc.math->FromInteger(rc.width, v, false);
                break;
              }
              r = rc.width == 64 ? std::bit_cast<std::uint64_t>(static_cast<double>(v)) : std::bit_cast<std::uint32_t>(static_cast<float>(v));
              break;
            case Op::OpUConvert: r = Mask(v, rc.width); break;
            case Op::OpSConvert: r = Mask(static_cast<std::uint64_t>(SignExtend(v, oc.width)), rc.width); break;
            default: r = rc.math ? rc.math->FromDouble(rc.width, F(v, oc)) : FBits(F(v, oc), rc); break;
          }
          Put(R(l, in.result), rc, i, r);
        }
      return;
    }
    case Op::OpBitcast: {
      const std::uint32_t words = p_.T(in.type).words;
      for (std::uint32_t l : lanes_) MoveWords(R(l, in.result), R(l, ops[0]), words);
      return;
    }
    case Op::OpCompositeConstruct:
    case Op::OpCompositeExtract:
    case Op::OpCompositeInsert: MoveComposite(in, [this](std::uint32_t l, std::uint32_t id) { return R(l, id); }); return;
    case Op::OpVectorShuffle: {
      const Comp rc = CompOf(in.type), ac = CompOf(TypeOfValue(ops[0]));
      for (std::uint32_t l : lanes_)
        for (std::uint32_t i = 0; i < rc.n; ++i) {
          const std::uint32_t k = ops[2 + i];
          const std::uint64_t v = k == 0xffffffffu ? 0 : k < ac.n ? Get(R(l, ops[0]), ac, k) : Get(R(l, ops[1]), ac, k - ac.n);
          Put(R(l, in.result), rc, i, v);
        }
      return;
    }
    case Op::OpVectorExtractDynamic:
    case Op::OpVectorInsertDynamic: {
      const bool insert = op == Op::OpVectorInsertDynamic;
      const Comp vc = CompOf(TypeOfValue(ops[0])), ic = CompOf(TypeOfValue(ops[insert ? 2 : 1]));
      for (std::uint32_t l : lanes_) {
        const std::uint64_t idx = Get(R(l, ops[insert ? 2 : 1]), ic, 0);
        if (idx >= vc.n) Fail(in, fmt::format("component {} of a {}-component vector", idx, vc.n));
        if (insert) {
          MoveWords(R(l, in.result), R(l, ops[0]), vc.n * vc.words);
          Put(R(l, in.result), vc, static_cast<std::uint32_t>(idx), Get(R(l, ops[1]), vc, 0));
        } else {
          Put(R(l, in.result), vc, 0, Get(R(l, ops[0]), vc, static_cast<std::uint32_t>(idx)));
        }
      }
      return;
    }
    default: Fail(in, "not executed by the simulator");
  }
}

// An add or subtract whose operand is a multiply of the same block, neither of them NoContraction:
// the worst-conformant device computes it as one fused operation.
void Workgroup::Contracted(const Inst& in) {
  const std::uint32_t entry = p_.contract[&in - p_.code.data()];
  const Inst& mul = p_.code[entry & ~kContractSecond];
  const bool second = entry & kContractSecond;  // the multiply is the second operand
  const auto ops = p_.Ops(in), m = p_.Ops(mul);
  const bool sub = static_cast<Op>(in.op) == Op::OpFSub;
  const Comp c = CompOf(in.type);
  const std::uint64_t sign = c.width == 64 ? 0x8000000000000000ull : 0x80000000ull;
  for (std::uint32_t l : lanes_)
    for (std::uint32_t i = 0; i < c.n; ++i) {
      std::uint64_t x = Get(R(l, m[0]), c, i);
      const std::uint64_t y = Get(R(l, m[1]), c, i);
      std::uint64_t other = Get(R(l, ops[second ? 0 : 1]), c, i);
      if (sub && !second) other ^= sign;  // x*y - other
      if (sub && second) x ^= sign;       // other - x*y = (-x)*y + other
      Put(R(l, in.result), c, i, math_->Fused(c.width, x, y, other));
    }
}

// Long: one case per GLSL.std.450 instruction.
void Workgroup::Extended(const Inst& in) {
  const auto all = p_.Ops(in);
  if (all[0] != p_.glsl_set) Fail(in, "an extended instruction of a set other than GLSL.std.450");
  const std::uint32_t inst = all[1];
  const auto args = all.subspan(2);
  const Comp rc = CompOf(in.type);
  const auto add = FAdd, mul = FMul, sub = FSub, div = FDiv;
  const auto sqrt = [](const Comp& c, std::uint64_t a) {
    if (c.math) return c.math->Binary(FloatOpKind::kSqrt, c.width, a, a);
    return FloatOp(c, a, a, [](float x, float) { return std::sqrt(x); }, [](double x, double) { return std::sqrt(x); });
  };
  const auto fmin = [](const Comp& c, std::uint64_t a, std::uint64_t b) { return FMin(c, a, b); };
  const auto fmax = [](const Comp& c, std::uint64_t a, std::uint64_t b) { return FMax(c, a, b); };
  const auto dot = [&](std::uint32_t l, std::uint32_t a, std::uint32_t b) {
    const Comp c = CompOf(TypeOfValue(a));
    std::uint64_t s = 0;
    for (std::uint32_t i = 0; i < c.n; ++i) {
      const std::uint64_t p = mul(c, Get(R(l, a), c, i), Get(R(l, b), c, i));
      s = i == 0 ? p : add(c, s, p);
    }
    return s;
  };
  const auto one = [](const Comp& c) { return FBits(1.0, c); };
  for (std::uint32_t l : lanes_) {
    std::uint32_t* out = R(l, in.result);
    const auto arg = [&](std::size_t k, std::uint32_t i) { return Get(R(l, args[k]), CompOf(TypeOfValue(args[k])), i); };
    switch (static_cast<GLSLstd450>(inst)) {
      case GLSLstd450Length: Put(out, rc, 0, sqrt(rc, dot(l, args[0], args[0]))); continue;
      case GLSLstd450Normalize: {
        const std::uint64_t len = sqrt(rc, dot(l, args[0], args[0]));
        for (std::uint32_t i = 0; i < rc.n; ++i) Put(out, rc, i, div(rc, arg(0, i), len));
        continue;
      }
      case GLSLstd450Cross:
        for (std::uint32_t i = 0; i < 3; ++i) {
          const std::uint32_t j = (i + 1) % 3, k = (i + 2) % 3;
          Put(out, rc, i, sub(rc, mul(rc, arg(0, j), arg(1, k)), mul(rc, arg(1, j), arg(0, k))));
        }
        continue;
      default: break;
    }
    for (std::uint32_t i = 0; i < rc.n; ++i) {
      const std::uint64_t a = arg(0, i);
      const std::uint64_t sign = rc.width == 64 ? 0x8000000000000000ull : 0x80000000ull;
      std::uint64_t r = 0;
      switch (static_cast<GLSLstd450>(inst)) {
        case GLSLstd450FAbs: r = a & ~sign; break;
        case GLSLstd450SAbs: r = Mask(static_cast<std::uint64_t>(std::abs(SignExtend(a, rc.width))), rc.width); break;
        case GLSLstd450FSign: {
          const double x = F(a, rc);
          r = FBits(x > 0 ? 1.0 : x < 0 ? -1.0 : 0.0, rc);
          break;
        }
        case GLSLstd450Floor: r = FBits(std::floor(F(a, rc)), rc); break;
        case GLSLstd450Ceil: r = FBits(std::ceil(F(a, rc)), rc); break;
        case GLSLstd450Trunc: r = FBits(std::trunc(F(a, rc)), rc); break;
        case GLSLstd450RoundEven: r = FBits(std::nearbyint(F(a, rc)), rc); break;
        case GLSLstd450Fract: r = sub(rc, a, FBits(std::floor(F(a, rc)), rc)); break;
        case GLSLstd450Sqrt: r = sqrt(rc, a); break;
        case GLSLstd450InverseSqrt: r = rc.math ? rc.math->Binary(FloatOpKind::kInverseSqrt, rc.width, a, a) : div(rc, one(rc), sqrt(rc, a)); break;
        case GLSLstd450FMin: r = fmin(rc, a, arg(1, i)); break;
        case GLSLstd450FMax: r = fmax(rc, a, arg(1, i)); break;
        case GLSLstd450FClamp: r = fmin(rc, fmax(rc, a, arg(1, i)), arg(2, i)); break;
        case GLSLstd450UMin: r = std::min(a, arg(1, i)); break;
        case GLSLstd450UMax: r = std::max(a, arg(1, i)); break;
        case GLSLstd450UClamp: r = std::min(std::max(a, arg(1, i)), arg(2, i)); break;
        case GLSLstd450SMin: r = Mask(static_cast<std::uint64_t>(std::min(SignExtend(a, rc.width), SignExtend(arg(1, i), rc.width))), rc.width); break;
        case GLSLstd450SMax: r = Mask(static_cast<std::uint64_t>(std::max(SignExtend(a, rc.width), SignExtend(arg(1, i), rc.width))), rc.width); break;
        case GLSLstd450SClamp:
          r = Mask(static_cast<std::uint64_t>(std::min(std::max(SignExtend(a, rc.width), SignExtend(arg(1, i), rc.width)), SignExtend(arg(2, i), rc.width))),
                   rc.width);
          break;
        case GLSLstd450FMix: r = add(rc, mul(rc, a, sub(rc, one(rc), arg(2, i))), mul(rc, arg(1, i), arg(2, i))); break;
        case GLSLstd450Step: r = FBits(F(arg(1, i), rc) < F(a, rc) ? 0.0 : 1.0, rc); break;
        case GLSLstd450Fma:  // lavapipe never fuses; a device may
          r = rc.math ? rc.math->Fused(rc.width, a, arg(1, i), arg(2, i)) : add(rc, mul(rc, a, arg(1, i)), arg(2, i));
          break;
        case GLSLstd450FindILsb: r = a == 0 ? 0xffffffffu : static_cast<std::uint64_t>(std::countr_zero(a)); break;
        case GLSLstd450FindUMsb: r = a == 0 ? 0xffffffffu : 63u - static_cast<std::uint64_t>(std::countl_zero(a)); break;
        case GLSLstd450FindSMsb: {
          const std::uint64_t v = (SignExtend(a, 32) < 0) ? Mask(~a, 32) : a;
          r = v == 0 ? 0xffffffffu : 63u - static_cast<std::uint64_t>(std::countl_zero(v));
          break;
        }
        default: Fail(in, fmt::format("GLSL.std.450 {} is not executed by the simulator", NameOf("GLSL.std.450", inst)));
      }
      Put(out, rc, i, r);
    }
  }
}

// Long: one case per subgroup operation.
void Workgroup::Subgroup(const Inst& in) {
  const auto ops = p_.Ops(in);
  const auto op = static_cast<Op>(in.op);
  if (R(lanes_[0], ops[0])[0] != static_cast<std::uint32_t>(spv::Scope::Subgroup)) Fail(in, "a group operation at a scope other than the subgroup");
  const std::uint32_t first = lanes_.front();
  switch (op) {
    case Op::OpGroupNonUniformElect:
      for (std::uint32_t l : lanes_) R(l, in.result)[0] = l == first;
      return;
    case Op::OpGroupNonUniformAll:
    case Op::OpGroupNonUniformAny: {
      bool all = true, any = false;
      for (std::uint32_t l : lanes_) {
        all &= R(l, ops[1])[0] != 0;
        any |= R(l, ops[1])[0] != 0;
      }
      for (std::uint32_t l : lanes_) R(l, in.result)[0] = op == Op::OpGroupNonUniformAll ? all : any;
      return;
    }
    case Op::OpGroupNonUniformBallot: {
      std::uint32_t bits[4] = {0, 0, 0, 0};
      for (std::uint32_t l : lanes_)
        if (R(l, ops[1])[0]) bits[(l - sub_first_) / 32] |= 1u << ((l - sub_first_) % 32);
      for (std::uint32_t l : lanes_) std::memcpy(R(l, in.result), bits, sizeof bits);
      return;
    }
    case Op::OpGroupNonUniformBallotBitCount: {
      const auto group = static_cast<spv::GroupOperation>(ops[1]);
      for (std::uint32_t l : lanes_) {
        const std::uint32_t* v = R(l, ops[2]);
        const std::uint32_t id = l - sub_first_;
        const std::uint32_t limit = group == spv::GroupOperation::Reduce ? sg_ : group == spv::GroupOperation::InclusiveScan ? id + 1 : id;
        std::uint32_t n = 0;
        for (std::uint32_t b = 0; b < limit && b < 128; ++b) n += (v[b / 32] >> (b % 32)) & 1u;
        R(l, in.result)[0] = n;
      }
      return;
    }
    case Op::OpGroupNonUniformBallotFindLSB:
    case Op::OpGroupNonUniformBallotFindMSB:  // of a value's first SubgroupSize bits; none set: all ones
      for (std::uint32_t l : lanes_) {
        const std::uint32_t* v = R(l, ops[1]);
        std::uint32_t found = 0xffffffffu;
        for (std::uint32_t b = 0; b < sg_ && b < 128; ++b)
          if ((v[b / 32] >> (b % 32)) & 1u) {
            found = b;
            if (op == Op::OpGroupNonUniformBallotFindLSB) break;
          }
        R(l, in.result)[0] = found;
      }
      return;
    case Op::OpGroupNonUniformBroadcast:
    case Op::OpGroupNonUniformBroadcastFirst:
    case Op::OpGroupNonUniformShuffle: {
      const std::uint32_t words = p_.T(in.type).words;
      const Comp ic = op == Op::OpGroupNonUniformBroadcastFirst ? Comp{} : CompOf(TypeOfValue(ops[2]));
      const std::bitset<kMaxSubgroup> active = ActiveLanes();
      for (std::uint32_t l : lanes_) {
        std::uint32_t src = first;
        if (op != Op::OpGroupNonUniformBroadcastFirst) {
          const std::uint64_t id = Get(R(l, ops[2]), ic, 0);
          if (id >= sg_ || sub_first_ + id >= sub_end_) Fail(in, fmt::format("lane {} of a subgroup of {}", id, sub_end_ - sub_first_));
          src = sub_first_ + static_cast<std::uint32_t>(id);
        }
        // An inactive lane's value is undefined (initcheck says so): 0 here, not what its register
        // holds from an earlier invocation, so the bits do not depend on the schedule.
        if (Active(active, src)) MoveWords(R(l, in.result), R(src, ops[1]), words);
        else std::fill_n(R(l, in.result), words, 0u);
      }
      return;
    }
    default: {  // arithmetic: IAdd, UMin, UMax, FMin, FMax as reductions and scans in lane order
      const auto group = static_cast<spv::GroupOperation>(ops[1]);
      const Comp c = CompOf(in.type);
      const auto combine = [&](std::uint64_t a, std::uint64_t b) -> std::uint64_t {
        switch (op) {
          case Op::OpGroupNonUniformIAdd: return Mask(a + b, c.width);
          case Op::OpGroupNonUniformUMin: return std::min(a, b);
          case Op::OpGroupNonUniformUMax: return std::max(a, b);
          case Op::OpGroupNonUniformFMin: return FMin(c, a, b);
          default: return FMax(c, a, b);
        }
      };
      std::uint64_t identity = 0;
      if (op == Op::OpGroupNonUniformUMin) identity = Mask(~0ull, c.width);
      if (op == Op::OpGroupNonUniformFMin) identity = FBits(std::numeric_limits<double>::infinity(), c);
      if (op == Op::OpGroupNonUniformFMax) identity = FBits(-std::numeric_limits<double>::infinity(), c);
      for (std::uint32_t i = 0; i < c.n; ++i) {
        std::uint64_t total = identity;
        bool started = false;
        std::vector<std::uint64_t>& before = scan_;
        before.assign(lanes_.size(), 0);
        for (std::size_t k = 0; k < lanes_.size(); ++k) {
          before[k] = total;
          const std::uint64_t v = Get(R(lanes_[k], ops[2]), c, i);
          total = started ? combine(total, v) : (op == Op::OpGroupNonUniformIAdd ? combine(identity, v) : v);
          started = true;
          if (group == spv::GroupOperation::InclusiveScan) Put(R(lanes_[k], in.result), c, i, total);
        }
        for (std::size_t k = 0; k < lanes_.size(); ++k) {
          if (group == spv::GroupOperation::Reduce) Put(R(lanes_[k], in.result), c, i, total);
          if (group == spv::GroupOperation::ExclusiveScan) Put(R(lanes_[k], in.result), c, i, before[k]);
        }
      }
      return;
    }
  }
}

void Workgroup::Atomic(const Inst& in) {
  const auto ops = p_.Ops(in);
  const auto op = static_cast<Op>(in.op);
  const Comp c = CompOf(op == Op::OpAtomicStore ? TypeOfValue(ops[3]) : in.type);
  const std::size_t bytes = c.words * 4;
  for (std::uint32_t l : lanes_) {
    std::uint8_t* mem = Address(in, l, ops[0], bytes, AccessKind::kAtomic);
    std::uint32_t w[2] = {0, 0};
    std::memcpy(w, mem, bytes);
    const std::uint64_t old = Get(w, c, 0);
    std::uint64_t next = old;
    const auto value = [&](std::size_t k) { return Get(R(l, ops[k]), c, 0); };
    switch (op) {
      case Op::OpAtomicLoad: break;
      case Op::OpAtomicStore: next = value(3); break;
      case Op::OpAtomicExchange: next = value(3); break;
      case Op::OpAtomicCompareExchange: next = old == value(5) ? value(4) : old; break;
      case Op::OpAtomicIAdd: next = Mask(old + value(3), c.width); break;
      case Op::OpAtomicISub: next = Mask(old - value(3), c.width); break;
      case Op::OpAtomicUMin: next = std::min(old, value(3)); break;
      case Op::OpAtomicUMax: next = std::max(old, value(3)); break;
      case Op::OpAtomicSMin: next = SignExtend(value(3), c.width) < SignExtend(old, c.width) ? value(3) : old; break;
      case Op::OpAtomicSMax: next = SignExtend(value(3), c.width) > SignExtend(old, c.width) ? value(3) : old; break;
      case Op::OpAtomicAnd: next = old & value(3); break;
      case Op::OpAtomicOr: next = old | value(3); break;
      default: next = old ^ value(3); break;
    }
    Put(w, c, 0, next);
    std::memcpy(mem, w, bytes);
    if (op != Op::OpAtomicStore) Put(R(l, in.result), c, 0, old);
  }
}
}  // namespace

void Run(const Program& program, const Dispatch& dispatch, ExecStats& stats) {
  std::unique_ptr<StorageCheck> storage_check;
  if (dispatch.checks.On(Checker::kRacecheck)) {
    std::vector<std::size_t> words;
    for (const Binding& b : dispatch.bindings) words.push_back(b.bytes / 4);
    storage_check = std::make_unique<StorageCheck>(words);
  }
  Workgroup wg(program, dispatch, stats, storage_check.get());
  const std::uint64_t count = std::uint64_t{dispatch.groups[0]} * dispatch.groups[1] * dispatch.groups[2];
  if (count > 0xffffffffull) throw SimError(fmt::format("{}: {} workgroups in one dispatch", program.name, count));
  for (std::uint32_t linear : ScheduleOrder(static_cast<std::uint32_t>(count), dispatch.schedule, dispatch.dispatch_index)) {
    const std::uint32_t g[3] = {linear % dispatch.groups[0], (linear / dispatch.groups[0]) % dispatch.groups[1],
                                linear / (dispatch.groups[0] * dispatch.groups[1])};
    wg.Run(g);
    ++stats.workgroups;
  }
}

}  // namespace rayspace::sim
