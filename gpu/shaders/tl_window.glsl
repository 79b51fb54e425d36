// The window of one traversal list (emu ListWindow in emu/src/tl.cpp, operation for operation): the
// part [head, tail) of [begin, end) outside which every triangle lies beyond a plane. The including
// kernel declares the buffers `escapes` (int), `words` (uvec4) and `vertices` (vec4) and the tests
// `bool SphereRejected(vec4)` and `bool TriangleRejected(vec3, vec3, vec3)` before including it.
// Head: skip a rejected subtree, enter a sphere that is not, up to the first triangle kept; the head
// is the element after the last subtree skipped. Tail: the last subtree of the chain after the head
// that is not rejected, one tree level at a time.

bool IsTri(uint i) { return escapes[i] == 1 || escapes[i] == 0; }

bool Rejected(uint i) {
  const uvec4 w = words[i];
  if (!IsTri(i)) return SphereRejected(uintBitsToFloat(w));
  return TriangleRejected(vertices[w.x].xyz, vertices[w.y].xyz, vertices[w.z].xyz);
}

// The element after i's subtree (a sphere's escape -1: the list's end).
uint Next(uint i, uint end) {
  const int e = escapes[i];
  return IsTri(i) ? i + 1u : e == -1 ? end : i + uint(e);
}

uvec2 ListWindow(uint begin, uint end) {
  uint head = begin, i = begin;
  bool found = false;
  for (uint b = 0u; !found && i < end && b <= end / kTlLoopBlock; ++b)
    for (uint j = 0u; !found && i < end && j < kTlLoopBlock; ++j) {
      if (Rejected(i)) {
        i = Next(i, end);
        head = i;
      } else if (IsTri(i)) {
        found = true;
      } else {
        i += 1u;
      }
    }
  if (!found) return uvec2(end, end);
  uint lo = head, hi = end, tail = end;
  for (uint level = 0u; level <= kTlMaxDepth + 1u; ++level) {
    uint last = hi, x = lo;
    for (uint b = 0u; x < hi && b <= end / kTlLoopBlock; ++b)
      for (uint j = 0u; x < hi && j < kTlLoopBlock; ++j) {
        if (!Rejected(x)) last = x;
        x = Next(x, end);
      }
    if (last == hi) {
      tail = lo;
      break;
    }
    if (IsTri(last)) {
      tail = last + 1u;
      break;
    }
    lo = last + 1u;
    hi = Next(last, end);
    tail = hi;
  }
  return uvec2(head, tail);
}
