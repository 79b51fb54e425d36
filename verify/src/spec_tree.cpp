// The relaxed device model of the object-tree descent (docs/numerics.md, "The relaxed device model"):
// a candidate's cone-sphere test may go the other way on a conformant device only where the
// emulator's own test, evaluated in SpecReal, meets a decision a permitted rounding can flip. The
// candidates themselves (which pairs, in which slots) are integer decisions of the inputs, except the
// side a pair refines (SplitCone: products and sums, to nearest or toward zero as the device rounds):
// a call whose differing pair may refine the other side is left unmodelled, and its diff says only
// "different".
#include <algorithm>
#include <cstdint>

#include <fmt/format.h>

#include "rayspace/emu/cone.h"
#include "rayspace/emu/object_tree_traverse.h"
#include "rayspace/verify/call_codec.h"
#include "rayspace/verify/spec_real.h"
#include "spec_tally.h"

namespace rayspace::verify {
namespace {

using emu::ConeTreeView;
using emu::ObjectTreeView;
using emu::TreeCounts;

// Could some conformant device decide candidate (cone, item)'s test the other way?
bool TestMayFlip(const ConeTreeView& cones, const ObjectTreeView& tree, std::uint32_t cone, std::uint32_t item, float eps,
                 bool flush) {
  ScopedSpecTrace trace(flush);
  (void)emu::cone::TestOf<SpecReal>(emu::TreeConeNode(cones, cone), emu::TreeItemSphere(tree, item), eps);
  return trace.trace().ambiguous != 0;
}

// Could some conformant device refine pair (cone, item) on the other side?
bool SplitMayFlip(const ConeTreeView& cones, const ObjectTreeView& tree, std::uint32_t cone, std::uint32_t item, bool flush) {
  if ((item & layout::kTreeItemTriangle) != 0 || (cone >> layout::kTreeLevelShift) == 0) return false;  // one side only
  ScopedSpecTrace trace(flush);
  (void)emu::SplitConeOf<SpecReal>(emu::TreeConeNode(cones, cone), tree.tree_spheres[item]);
  return trace.trace().ambiguous != 0;
}

// The counts a device must report: the emulator's with each candidate whose test went the other way
// moved between hit and miss (`gained` hits, `lost` hits).
class CountsModel {
 public:
  CountsModel(const ConeTreeView& cones, const ObjectTreeView& tree)
      : tree_(tree), gained_(emu::EmptyTreeCounts(cones, tree)), lost_(gained_) {}
  void Flipped(std::uint32_t cone, std::uint32_t item, bool device_hit) {
    emu::CountTreeTests(device_hit ? gained_ : lost_, tree_, cone, item, 0, 1);
  }
  void Check(const TreeCounts& emulator, const TreeCounts& device, SpecTally& t) const {
    if (emulator.cone_tests.size() != device.cone_tests.size() || emulator.node_tests.size() != device.node_tests.size()) {
      t.Beyond("counts: sizes differ");
      return;
    }
    TreeCounts want = emulator, have = device;
    want.Add(gained_);
    have.Add(lost_);
    if (!(want == have)) t.Beyond("counts: not the tests and hits of the device's own decisions (integers, exact everywhere)");
  }

 private:
  const ObjectTreeView& tree_;
  TreeCounts gained_, lost_;
};

// tree.roots and tree.test: a flag per candidate slot. The slots' candidates must match; a differing
// flag is within the spec when it is 0 or the candidate's kind on both sides and the candidate's test
// may flip; the counts must be the device's own flags' counts.
SpecVerdict TallySlots(const emu::TreeSlots& e, const emu::TreeSlots& a, const ConeTreeView& cones, const ObjectTreeView& tree,
                       float eps, bool flush) {
  SpecTally t;
  if (e.flags.size() != a.flags.size() || a.pairs.cone.size() != a.flags.size() || a.pairs.item.size() != a.flags.size()) {
    t.Beyond("flags, cone, item: sizes differ");
    return t.Done();
  }
  if (e.pairs.cone != a.pairs.cone || e.pairs.item != a.pairs.item) {
    t.Beyond("cone, item: a slot's candidate is an integer decision of the inputs");
    return t.Done();
  }
  CountsModel counts(cones, tree);
  for (std::size_t i = 0; i < e.flags.size(); ++i) {
    if (e.flags[i] == a.flags[i]) continue;
    const std::uint32_t cone = e.pairs.cone[i], item = e.pairs.item[i];
    const std::uint8_t kind = emu::TreePairKind(cone, item);
    const bool values = (e.flags[i] == 0 || e.flags[i] == kind) && (a.flags[i] == 0 || a.flags[i] == kind);
    if (values && TestMayFlip(cones, tree, cone, item, eps, flush)) {
      t.Within();
      counts.Flipped(cone, item, a.flags[i] != 0);
    } else {
      t.Beyond(fmt::format("flags[{}]: {} where every conformant device gives {}", i, a.flags[i], e.flags[i]));
    }
  }
  counts.Check(e.counts, a.counts, t);
  return t.Done();
}

SpecVerdict TreeRoots(const BufferSet& in, const BufferSet& e, const BufferSet& a, bool flush) {
  const DecodedCall<emu::call::TreeRoots> d = DecodeCall<emu::call::TreeRoots>(in);
  return TallySlots(DecodeOutputs(e, d.call), DecodeOutputs(a, d.call), d.call.cones, d.call.tree, d.call.eps, flush);
}

// The pair whose candidates slot i holds (offsets: the exclusive scan of the pairs' counts).
std::size_t PairOfSlot(std::span<const std::uint32_t> offsets, std::size_t slot) {
  return static_cast<std::size_t>(std::upper_bound(offsets.begin(), offsets.end(), slot) - offsets.begin()) - 1;
}

SpecVerdict TreeTest(const BufferSet& in, const BufferSet& e, const BufferSet& a, bool flush) {
  const DecodedCall<emu::call::TreeTest> d = DecodeCall<emu::call::TreeTest>(in);
  const emu::call::TreeTest& c = d.call;
  const emu::TreeSlots es = DecodeOutputs(e, c), as = DecodeOutputs(a, c);
  const std::size_t n = std::min({es.flags.size(), as.flags.size(), as.pairs.cone.size(), as.pairs.item.size()});
  for (std::size_t i = 0; i < n; ++i) {
    if (es.flags[i] == as.flags[i] && es.pairs.cone[i] == as.pairs.cone[i] && es.pairs.item[i] == as.pairs.item[i]) continue;
    const std::size_t p = PairOfSlot(c.offsets, i);
    if (p < c.pair_cone.size() && SplitMayFlip(c.cones, c.tree, c.pair_cone[p], c.pair_item[p], flush)) return {};
  }
  return TallySlots(es, as, c.cones, c.tree, c.eps, flush);
}

// tree.expand: a pair's candidate count is an integer of the inputs, unless its side may go either way.
SpecVerdict TreeExpand(const BufferSet& in, const BufferSet& e, const BufferSet& a, bool flush) {
  const DecodedCall<emu::call::TreeExpand> d = DecodeCall<emu::call::TreeExpand>(in);
  const emu::call::TreeExpand& c = d.call;
  const std::vector<std::uint32_t> ec = e.Get<std::uint32_t>("counts"), ac = a.Get<std::uint32_t>("counts");
  SpecTally t;
  if (ec.size() != ac.size() || ec.size() != c.pair_cone.size()) {
    t.Beyond("counts: sizes differ");
    return t.Done();
  }
  for (std::size_t p = 0; p < ec.size(); ++p) {
    if (ec[p] == ac[p]) continue;
    const std::uint32_t cone = c.pair_cone[p], item = c.pair_item[p];
    const bool other = !emu::TreeSplitsCone(c.cones, c.tree, cone, item);
    if (SplitMayFlip(c.cones, c.tree, cone, item, flush) && ac[p] == emu::ExpandTreePair(c.cones, c.tree, cone, item, other).Count())
      t.Within();
    else
      t.Beyond(fmt::format("counts[{}]: {} candidates where every conformant device refines the pair into {}", p, ac[p], ec[p]));
  }
  return t.Done();
}

// One list of tree.step's output (next or final) walked in slot order beside the emulator's.
struct ListWalk {
  const std::vector<std::uint32_t>& cone;
  const std::vector<std::uint32_t>& item;
  std::size_t at = 0;
  bool Takes(std::uint32_t c, std::uint32_t i) {
    const bool here = at < cone.size() && at < item.size() && cone[at] == c && item[at] == i;
    at += here;
    return here;
  }
};

// tree.step: the kept candidates in slot order, split into the pairs that go on and the final ones.
// The device's lists must be the emulator's but for candidates whose test may flip.
SpecVerdict TreeStep(const BufferSet& in, const BufferSet& e, const BufferSet& a, bool flush) {
  const DecodedCall<emu::call::TreeStep> d = DecodeCall<emu::call::TreeStep>(in);
  const emu::call::TreeStep& c = d.call;
  const emu::TreeRound er = DecodeOutputs(e, c), ar = DecodeOutputs(a, c);
  SpecTally t;
  CountsModel counts(c.cones, c.tree);
  ListWalk e_next{er.next.cone, er.next.item}, e_final{er.final.cone, er.final.item};
  ListWalk a_next{ar.next.cone, ar.next.item}, a_final{ar.final.cone, ar.final.item};
  for (std::size_t p = 0; p < c.pair_cone.size(); ++p) {
    const std::uint32_t cone = c.pair_cone[p], item = c.pair_item[p];
    const emu::TreeExpansion x = emu::ExpandTreePair(c.cones, c.tree, cone, item, emu::TreeSplitsCone(c.cones, c.tree, cone, item));
    bool split_checked = false;
    for (std::uint32_t k = 0; k < x.Count(); ++k) {
      const auto [kc, ki] = emu::TreeCandidate(x, cone, item, k);
      const bool final = emu::TreePairKind(kc, ki) == 2;
      const bool kept = (final ? e_final : e_next).Takes(kc, ki), device = (final ? a_final : a_next).Takes(kc, ki);
      if (kept == device) continue;
      if (!split_checked && SplitMayFlip(c.cones, c.tree, cone, item, flush)) return {};
      split_checked = true;
      if (TestMayFlip(c.cones, c.tree, kc, ki, c.eps, flush)) {
        t.Within();
        counts.Flipped(kc, ki, device);
      } else {
        t.Beyond(fmt::format("{}: ({:#x}, {:#x}) {} where every conformant device {} it", final ? "final" : "next", kc, ki,
                             device ? "kept" : "dropped", device ? "drops" : "keeps"));
      }
    }
  }
  for (const auto& [walk, name] : {std::pair{&a_next, "next"}, std::pair{&a_final, "final"}})
    if (walk->at < walk->cone.size() || walk->cone.size() != walk->item.size())
      t.Beyond(fmt::format("{}[{}]: no candidate of any pair in slot order", name, walk->at));
  counts.Check(er.counts, ar.counts, t);
  return t.Done();
}

}  // namespace

SpecVerdict ClassifyTree(const std::string& method, const BufferSet& in, const BufferSet& expected, const BufferSet& actual,
                         bool flush_denormals) {
  if (method == "tree.roots") return TreeRoots(in, expected, actual, flush_denormals);
  if (method == "tree.expand") return TreeExpand(in, expected, actual, flush_denormals);
  if (method == "tree.test") return TreeTest(in, expected, actual, flush_denormals);
  if (method == "tree.step") return TreeStep(in, expected, actual, flush_denormals);
  return {};
}

}  // namespace rayspace::verify
