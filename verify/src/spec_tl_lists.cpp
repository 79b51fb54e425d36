// The relaxed device model of tl.lists (docs/numerics.md, "The relaxed device model"). A list is the
// object tree flattened in an order that rounds: each node's children (own triangles, then child
// nodes) sorted by a key (a projection on the list's direction, tl::SphereKey, tl::TriangleKey), and
// with culling, triangles dropped by a test that rounds (tl::CulledOf). A device's list is within the
// spec when it is the tree flattened with culling decisions some device may take and, under every
// node, an order of the children that sorts them by (key, sibling) for key values each within its
// permitted interval: the same key on one device for every invocation that computes it, as for any
// function of the same inputs. The structure (escapes, words, the list's length) is integers and
// exact.
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "rayspace/emu/tl/layout.h"
#include "rayspace/emu/tl/streams.h"
#include "rayspace/emu/tl/walk_math.h"
#include "rayspace/verify/call_codec.h"
#include "spec_tally.h"

namespace rayspace::verify {
namespace {

using R = SpecReal;
using emu::tl::Escape;

emu::Vec3<R> ListsSpec3(glm::vec4 v) { return {R(v.x), R(v.y), R(v.z)}; }

// A float key as tl.cpp orders it (the bits of an ordered float, a NaN after everything).
std::uint32_t OrderedKey(float f) {
  if (std::isnan(f)) return ~0u;
  const std::uint32_t b = std::bit_cast<std::uint32_t>(f);
  return (b & 0x80000000u) ? ~b : b | 0x80000000u;
}

struct KeyRange {
  std::uint32_t lo = 0, hi = ~0u;
};

KeyRange RangeOf(R x) {
  if (x.any) return {};
  return {OrderedKey(x.lo), OrderedKey(x.hi)};
}

// One list's check: the device's list parsed along its escapes and held against the tree.
class ListCheck {
 public:
  ListCheck(const emu::call::TlLists& c, std::uint32_t k, std::span<const std::uint32_t> escapes, std::span<const glm::uvec4> words,
            std::uint32_t length, bool flush)
      : c_(c), k_(k), escapes_(escapes), words_(words), length_(length), flush_(flush) {
    const glm::vec4 d = c.directions[k];
    axis_ = {R(d.x), R(d.y), R(d.z)};
    shown_.assign(c.tree.tl_triangles.size(), false);
  }

  // Why the list is no flattening a conformant device may produce, or nothing.
  std::optional<std::string> Run() {
    if (length_ > escapes_.size()) return fmt::format("length {} beyond the list's {} slots", length_, escapes_.size());
    for (const std::uint32_t root : c_.tree.tl_roots)
      if (at_ < length_ && IsNode(at_, root))
        if (auto why = Node(root, at_)) return why;
    if (at_ != length_) return fmt::format("element {}: not the next root's sphere in the roots' order", at_);
    for (std::size_t r = 0; r < shown_.size(); ++r)
      if (!shown_[r] && !MayDrop(static_cast<std::uint32_t>(r)))
        return fmt::format("triangle reference {} missing, which no conformant device culls", r);
    return std::nullopt;
  }

 private:
  bool Triangle(std::uint32_t i) const { return emu::tl::IsTriangle(static_cast<Escape>(escapes_[i])); }
  glm::uvec4 SphereWord(std::uint32_t node) const {
    const glm::vec4 s = c_.tree.tl_spheres[node];
    return {std::bit_cast<std::uint32_t>(s.x), std::bit_cast<std::uint32_t>(s.y), std::bit_cast<std::uint32_t>(s.z),
            std::bit_cast<std::uint32_t>(s.w)};
  }
  glm::uvec4 TriangleWord(std::uint32_t ref) const { return c_.tree.tl_tri_words[c_.tree.tl_triangles[ref]]; }
  bool IsNode(std::uint32_t i, std::uint32_t node) const { return !Triangle(i) && words_[i] == SphereWord(node); }
  emu::Vec3<R> Vertex(std::uint32_t ref, int j) const { return ListsSpec3(c_.tree.tl_vertices[TriangleWord(ref)[j]]); }

  // The culling decision of a triangle reference: may a device keep it, may it drop it?
  std::pair<bool, bool> Cull(std::uint32_t ref) const {
    if (c_.cull == 0) return {true, false};
    ScopedSpecTrace trace(flush_);
    const bool culled = emu::tl::CulledOf(Vertex(ref, 0), Vertex(ref, 1), Vertex(ref, 2), static_cast<std::uint32_t>(c_.directions.size()), k_);
    const bool flip = trace.trace().ambiguous != 0;
    return {!culled || flip, culled || flip};
  }
  bool MayDrop(std::uint32_t ref) const { return Cull(ref).second; }

  // The key interval of sibling s of `parent` (own triangles first, then child nodes).
  KeyRange Key(std::uint32_t parent, std::uint32_t s) const {
    const glm::uvec4 l = c_.tree.tl_links[parent];
    ScopedSpecTrace trace(flush_);
    const bool earliest = c_.order == layout::kTlOrderEarliestFirst;
    if (s >= l.w) {
      const glm::vec4 sp = c_.tree.tl_spheres[l.x + s - l.w];
      const R p = emu::Dot(ListsSpec3(sp), axis_);
      return RangeOf(earliest ? p - R(sp.w) : p + R(sp.w));
    }
    // The device's key is one of its three projections, the least (or greatest) of its own values.
    R p[3];
    for (int j = 0; j < 3; ++j) p[j] = emu::Dot(Vertex(l.z + s, j), axis_);
    KeyRange k{~0u, 0};
    float lo = p[0].lo, hi = p[0].hi;
    for (int j = 0; j < 3; ++j) {
      if (p[j].any) return {};
      lo = earliest ? std::min(lo, p[j].lo) : std::max(lo, p[j].lo);
      hi = earliest ? std::min(hi, p[j].hi) : std::max(hi, p[j].hi);
    }
    k.lo = OrderedKey(lo);
    k.hi = OrderedKey(hi);
    return k;
  }

  // Is there a key per sibling, within its interval, that sorts `order` by (key, sibling)? Greedy:
  // each takes the least key its predecessor allows.
  bool Sortable(std::uint32_t parent, const std::vector<std::uint32_t>& order) const {
    std::uint64_t prev = 0;
    std::uint32_t prev_s = 0;
    bool first = true;
    for (const std::uint32_t s : order) {
      const KeyRange r = Key(parent, s);
      std::uint64_t key = std::max<std::uint64_t>(r.lo, prev);
      if (!first && key == prev && s < prev_s) ++key;
      if (key > r.hi) return false;
      prev = key;
      prev_s = s;
      first = false;
    }
    return true;
  }

  std::uint32_t Next(std::uint32_t i) const {
    const auto e = static_cast<Escape>(escapes_[i]);
    if (Triangle(i)) return i + 1;
    return e == emu::tl::kEscapeNone ? length_ : i + static_cast<std::uint32_t>(e);
  }

  // Node `node`'s sphere at element i, its subtree after it: own triangles and child nodes in an
  // order some device's keys give, each kept as some device's culling keeps it.
  std::optional<std::string> Node(std::uint32_t node, std::uint32_t i) {
    // A subtree reaching the list's end takes escape -1 (skipping it ends the walk), any other its length.
    const auto e = static_cast<Escape>(escapes_[i]);
    if (e != emu::tl::kEscapeNone && (e < 2 || i + static_cast<std::uint32_t>(e) >= length_))
      return fmt::format("element {}: sphere escape {} (the list ends at {})", i, e, length_);
    const std::uint32_t end = Next(i);
    const glm::uvec4 l = c_.tree.tl_links[node];
    std::vector<std::uint32_t> order, used(l.w + l.y, 0);
    std::uint32_t triangles_before = triangles_;
    for (std::uint32_t x = i + 1; x < end; x = Next(x)) {
      if (Next(x) > end) return fmt::format("element {}: its subtree runs past its parent's, which ends at {}", x, end);
      std::optional<std::uint32_t> sibling;
      for (std::uint32_t s = 0; s < l.w + l.y && !sibling; ++s) {
        if (used[s]) continue;
        if (s < l.w ? Triangle(x) && words_[x] == TriangleWord(l.z + s) : IsNode(x, l.x + s - l.w)) sibling = s;
      }
      if (!sibling) return fmt::format("element {}: no child of node {} left with its word", x, node);
      used[*sibling] = 1;
      order.push_back(*sibling);
      if (*sibling < l.w) {
        const std::uint32_t ref = l.z + *sibling;
        if (!Cull(ref).first) return fmt::format("element {}: triangle reference {} kept, which every device culls", x, ref);
        const auto te = static_cast<Escape>(escapes_[x]);
        if (te != (x + 1 == length_ ? emu::tl::kEscapeLast : Escape{1}))
          return fmt::format("element {}: triangle escape {}", x, te);
        shown_[ref] = true;
        ++triangles_;
      } else if (auto why = Node(l.x + *sibling - l.w, x)) {
        return why;
      }
    }
    if (triangles_ == triangles_before) return fmt::format("element {}: node {} kept with no triangle below it", i, node);
    if (!Sortable(node, order)) return fmt::format("node {}: its children in an order no permitted keys give", node);
    at_ = std::max(at_, end);
    return std::nullopt;
  }

  const emu::call::TlLists& c_;
  std::uint32_t k_;
  std::span<const std::uint32_t> escapes_;
  std::span<const glm::uvec4> words_;
  std::uint32_t length_;
  bool flush_;
  emu::Vec3<R> axis_;
  std::vector<bool> shown_;
  std::uint32_t triangles_ = 0, at_ = 0;
};

}  // namespace

SpecVerdict ClassifyTlLists(const BufferSet& in, const BufferSet& expected, const BufferSet& actual, bool flush) {
  const DecodedCall<emu::call::TlLists> d = DecodeCall<emu::call::TlLists>(in);
  const emu::call::TlLists& c = d.call;
  SpecTally t;
  const auto ee = expected.Get<std::uint32_t>("escapes"), ae = actual.Get<std::uint32_t>("escapes");
  const auto ew = expected.Get<glm::uvec4>("words"), aw = actual.Get<glm::uvec4>("words");
  const auto el = expected.Get<std::uint32_t>("lengths"), al = actual.Get<std::uint32_t>("lengths");
  const std::size_t K = c.directions.size(), E = c.tree.Elements();
  if (ae.size() != K * E || aw.size() != K * E || al.size() != K || ee.size() != ae.size() || ew.size() != aw.size()) {
    t.Beyond("escapes, words, lengths: a slot per (list, element) and a length per list");
    return t.Done();
  }
  for (std::size_t k = 0; k < K; ++k) {
    const auto span = [&](const auto& v) { return std::span(v).subspan(k * E, E); };
    const auto eq = [&](const auto& a, const auto& b) { return std::ranges::equal(span(a), span(b)); };
    if (el[k] == al[k] && eq(ee, ae) && eq(ew, aw)) continue;
    bool tail_zero = true;
    for (std::size_t i = al[k]; i < E && tail_zero; ++i) tail_zero = ae[k * E + i] == 0 && aw[k * E + i] == glm::uvec4(0);
    ListCheck check(c, static_cast<std::uint32_t>(k), span(ae), span(aw), al[k], flush);
    std::optional<std::string> why = tail_zero ? check.Run() : std::optional<std::string>("slots after the length written");
    if (why)
      t.Beyond(fmt::format("list {}: {}", k, *why));
    else
      t.Within();
  }
  return t.Done();
}

}  // namespace rayspace::verify
