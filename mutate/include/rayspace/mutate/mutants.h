// Mutants of the GLSL kernels (docs/verification.md): small syntactic changes a kernel developer
// could make by mistake, found by a tokenizer that knows GLSL's comments, preprocessor lines and
// layout qualifiers, each applied alone to one source file.
#pragma once
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace rayspace::mutate {

// The mutation operators.
inline constexpr std::string_view kComparison = "comparison";   // < <=, > >=, == !=
inline constexpr std::string_view kArithmetic = "arithmetic";   // + -, * /, += -=, *= /=, & |, && ||
inline constexpr std::string_view kConstant = "constant";       // an integer literal +1 or -1
inline constexpr std::string_view kFloatUlp = "float-ulp";      // a float literal one ulp up
inline constexpr std::string_view kBarrier = "barrier";         // a barrier call dropped
inline constexpr std::string_view kBinding = "binding";         // two buffers' bindings swapped
inline constexpr std::string_view kComponent = "component";     // .x .y .z .w swapped
inline constexpr std::string_view kLoopBound = "loop-bound";    // a for loop's bound +1 or -1

struct Mutation {
  std::string file;  // the source file's name, e.g. "trim.comp", "cone.glsl"
  std::string op;    // one of the operators above
  std::size_t offset = 0, length = 0;  // the replaced text
  std::string before, after;
  // A second edit, after the first (a binding swap changes both declarations); length2 0: none.
  std::size_t offset2 = 0, length2 = 0;
  std::string after2;
  int line = 0, column = 0;  // 1-based
  // Stable across runs and machines: file:line:column:op:after.
  std::string Id() const;
};

// Every mutation of `source` (the text of `file`), in source order.
std::vector<Mutation> Enumerate(std::string_view file, std::string_view source);
// `source` with m applied.
std::string Apply(std::string_view source, const Mutation& m);
// The files `source` includes with #include "...", in order.
std::vector<std::string> Includes(std::string_view source);
// The text of line `line` (1-based) of `source`, without its newline or leading blanks.
std::string LineText(std::string_view source, int line);
// Whether a survivor's recorded classification (docs/mutation-survivors.json) still applies to the
// mutant of its id: only while the mutant's line reads as it did when it was classified (LineText).
// An id names a line and a column, which edits elsewhere in the file move: a stale entry would
// otherwise label whatever mutant now has its id, e.g. call a real survivor equivalent.
bool ClassificationApplies(std::string_view recorded_source, std::string_view current_source);

// A deterministic order of `count` items for a seed: a Fisher-Yates shuffle driven by SplitMix64
// (specified here, not by the standard library, so every platform picks the same mutants).
std::vector<std::size_t> Shuffled(std::size_t count, std::uint64_t seed);
// A seed from text (a commit hash, a number): FNV-1a of the bytes, or the number itself.
std::uint64_t SeedOf(std::string_view text);

}  // namespace rayspace::mutate
