// The traversal lists' element layout (docs/traversal-lists.md), to be mirrored by a GLSL kernel.
// Toczek et al. store per element "an escape pointer of 32 bits and a word of 128 bits". They are
// kept as two arrays rather than one struct: std430 would pad a {int, uvec4} struct to 32 bytes
// (the uvec4 aligns to 16), while two arrays keep the paper's 20 bytes per element and let the
// loop read the escape, which it needs first, from a dense array.
#pragma once
#include <cstdint>

#include <glm/vec4.hpp>

namespace rayspace::emu::tl {

// The 128-bit word: a sphere as the float bits of (x, y, z, r), or a triangle as its three indices
// into the shared vertex array and its scene primitive id (the hit's id; the escape, not the word,
// says which of the two an element is).
using Word = glm::uvec4;
static_assert(sizeof(Word) == 16);

// The relative escape: the offset to the element's super-sibling (where a depth-first walk resumes
// once the element's subtree is done). It is 1 exactly for a triangle that has a next element, and
// at least 2 for a sphere, which always has a subtree. The paper's two special values end the walk
// when followed: 0 for the list's last element (always a triangle) and -1 for a sphere with no
// super-sibling (one on the list's last branch).
using Escape = std::int32_t;
static_assert(sizeof(Escape) == 4);
inline constexpr Escape kEscapeLast = 0;
inline constexpr Escape kEscapeNone = -1;

// A triangle is an element whose escape is 1 or 0.
inline bool IsTriangle(Escape e) { return e == 1 || e == kEscapeLast; }

// A shared vertex: xyz and w = 1 (16 bytes, a std430 vec4 array's stride).
using Vertex = glm::vec4;
static_assert(sizeof(Vertex) == 16);

}  // namespace rayspace::emu::tl
