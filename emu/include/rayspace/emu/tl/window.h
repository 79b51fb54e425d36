// The window of one traversal list that a group of rays walks (tl.heads, tl.cells; tl_window.glsl),
// from a rejection test per element: the emulated passes' and the relaxed model's.
#pragma once
#include <cstdint>
#include <span>

#include <glm/vec2.hpp>

#include "rayspace/emu/tl/layout.h"
#include "rayspace/layout.h"

namespace rayspace::emu::tl {

// The window of one list (tl_window.glsl): the part [head, tail) of [begin, end) outside which every
// triangle is `rejected` (lies beyond a plane; a rejected sphere holds only rejected triangles).
// Head: in list order, skip a subtree that is rejected and enter a sphere that is not, up to the first
// triangle not rejected; the head is the element right after the last subtree skipped (begin if
// none). A walk may start at any element (escapes are relative: it walks the rest of the list as if
// every ancestor's sphere were hit), so the spheres entered before the last skip are not tested;
// those after it are, so the walk keeps every sphere test that prunes nothing the head skips.
// Tail: from the head, along the chain of subtrees to the list's end, the last one not rejected,
// then the same inside it, one level at a time, until a triangle or a sphere none of whose children
// is kept (every element after the tail is rejected).
template <typename Rejected>
glm::uvec2 ListWindow(std::span<const std::uint32_t> escapes, std::uint32_t begin, std::uint32_t end, Rejected&& rejected) {
  auto triangle = [&](std::uint32_t i) { return IsTriangle(static_cast<Escape>(escapes[i])); };
  auto next = [&](std::uint32_t i) {  // the element after i's subtree (a sphere's escape -1: the end)
    const Escape e = static_cast<Escape>(escapes[i]);
    return triangle(i) ? i + 1u : e == kEscapeNone ? end : i + static_cast<std::uint32_t>(e);
  };
  std::uint32_t head = begin, i = begin;
  bool found = false;
  for (std::uint32_t b = 0; !found && i < end && b <= end / layout::kTlLoopBlock; ++b)
    for (std::uint32_t j = 0; !found && i < end && j < layout::kTlLoopBlock; ++j) {
      if (rejected(i))
        head = i = next(i);  // skipped: the walk starts after it at the earliest
      else if (triangle(i))
        found = true;
      else
        i += 1;  // into the sphere
    }
  if (!found) return {end, end};
  std::uint32_t lo = head, hi = end, tail = end;
  for (std::uint32_t level = 0; level <= layout::kTlMaxDepth + 1; ++level) {
    std::uint32_t last = hi, x = lo;  // last: the last subtree of [lo, hi) not rejected, hi for none
    for (std::uint32_t b = 0; x < hi && b <= end / layout::kTlLoopBlock; ++b)
      for (std::uint32_t j = 0; x < hi && j < layout::kTlLoopBlock; ++j) {
        if (!rejected(x)) last = x;
        x = next(x);
      }
    if (last == hi) {  // none kept below the sphere before [lo, hi): it ends the window
      tail = lo;
      break;
    }
    if (triangle(last)) {
      tail = last + 1;
      break;
    }
    lo = last + 1;
    hi = next(last);
    tail = hi;  // if the levels run out: the whole sphere's subtree
  }
  return {head, tail};
}

}  // namespace rayspace::emu::tl
