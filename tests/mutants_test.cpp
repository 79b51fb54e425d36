// The mutants `rayspace mutate` makes of the GLSL kernels (rayspace/mutate/mutants.h): each operator on a
// hand-written kernel with known sites, what the tokenizer must leave alone (comments, directives,
// layout qualifiers, the planted faults' numbers), the two-site binding swap, and the seeded choice.
#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

#include "rayspace/mutate/mutants.h"
#include "test_util.h"

using namespace rayspace;

namespace {

const char* const kKernel = R"(#version 460
#include "common.glsl"
// a < b in a comment, 1u + 2u
#define STEP(x) ((x) + 1u)
layout(local_size_x_id = 1) in;
layout(std430, binding = kBindIn) readonly buffer In { uint a[]; };
layout(std430, binding = kBindOut) writeonly buffer Out { uint b[]; };
void main() {
  const uint i = gl_GlobalInvocationID.x;
  for (uint k = 0u; k < pc.n; ++k) b[i] = a[k] * 3u - STEP(i);
  if (kFault == 2u) return;
  barrier();
  const float f = -0.5;
}
)";

std::vector<mutate::Mutation> Of(std::string_view op, const std::vector<mutate::Mutation>& all) {
  std::vector<mutate::Mutation> out;
  for (const auto& m : all)
    if (m.op == op) out.push_back(m);
  return out;
}

std::string Texts(const std::vector<mutate::Mutation>& ms) {
  std::string s;
  for (const auto& m : ms) s += m.before + ">" + m.after + " ";
  return s;
}

}  // namespace

TEST_CASE("mutants: every operator at its known sites, nothing in comments, directives or layouts") {
  const auto all = mutate::Enumerate("k.comp", kKernel);
  // Comparisons: k < pc.n, kFault == 2u.
  CHECK(Texts(Of(mutate::kComparison, all)) == "<><= ==>!= ");
  // Arithmetic: *, - (binary), + inside the macro body; the unary minus of -0.5 is left alone.
  CHECK(Texts(Of(mutate::kArithmetic, all)) == "+>- *>/ ->+ ");
  // Integer literals +1 and -1 (not below zero); the macro's 1u, the loop's 0u, 3u; kFault's 2u is
  // the planted fault's number, not the kernel's work; #version 460 and local_size_x_id = 1 are not code.
  CHECK(Texts(Of(mutate::kConstant, all)) == "1u>2u 1u>0u 0u>1u 3u>4u 3u>2u ");
  CHECK(Texts(Of(mutate::kFloatUlp, all)) == "0.5>0.50000006 ");
  CHECK(Texts(Of(mutate::kBarrier, all)) == "barrier()> ");
  CHECK(Texts(Of(mutate::kComponent, all)) == "x>y ");
  CHECK(Texts(Of(mutate::kLoopBound, all)) == "pc.n>(pc.n) + 1 pc.n>(pc.n) - 1 ");
  // Sites in source order, with their lines.
  CHECK(std::is_sorted(all.begin(), all.end(), [](const auto& a, const auto& b) { return a.offset < b.offset; }));
  const auto cmp = Of(mutate::kComparison, all);
  CHECK(cmp[0].line == 10);
  CHECK(mutate::LineText(kKernel, cmp[0].line).rfind("for (uint k = 0u;", 0) == 0);
}

TEST_CASE("mutants: applied alone, each changes only its site; a binding swap changes both declarations") {
  const auto all = mutate::Enumerate("k.comp", kKernel);
  const auto swaps = Of(mutate::kBinding, all);
  REQUIRE(swaps.size() == 1);
  const std::string swapped = mutate::Apply(kKernel, swaps[0]);
  CHECK(swapped.find("binding = kBindOut) readonly buffer In") != std::string::npos);
  CHECK(swapped.find("binding = kBindIn) writeonly buffer Out") != std::string::npos);
  std::set<std::string> ids;
  for (const auto& m : all) {
    const std::string s = mutate::Apply(kKernel, m);
    CHECK(s != kKernel);
    CHECK(s.substr(0, m.offset) == std::string(kKernel).substr(0, m.offset));
    ids.insert(m.Id());
  }
  CHECK(ids.size() == all.size());  // ids name one mutant each
}

TEST_CASE("mutants: a float literal one ulp up reads back as that float") {
  const auto all = mutate::Enumerate("f.glsl", "float f() { return 1.0 + 3.4e38 + 0.1f; }\n");
  const auto ulps = Of(mutate::kFloatUlp, all);
  REQUIRE(ulps.size() == 3);
  for (const auto& m : ulps) {
    std::string before = m.before, after = m.after;
    if (before.back() == 'f') before.pop_back(), after.pop_back();
    CHECK(std::strtof(after.c_str(), nullptr) == std::nextafter(std::strtof(before.c_str(), nullptr), INFINITY));
  }
}

TEST_CASE("mutants: zero one ulp up is the smallest subnormal, written as its bits") {
  const auto ulps = Of(mutate::kFloatUlp, mutate::Enumerate("f.glsl", "bool f(float x) { return x < 0.0 || x > -0.0; }\n"));
  REQUIRE(ulps.size() == 2);
  CHECK(ulps[0].after == "uintBitsToFloat(0x00000001u)");
  CHECK(ulps[1].after == "uintBitsToFloat(0x00000001u)");  // a unary minus is not part of the literal
}

TEST_CASE("mutants: every kernel's mutants apply, and the choice is a seeded permutation") {
  std::size_t total = 0;
  for (const auto& e : std::filesystem::directory_iterator(test::SourceDir() / "gpu" / "shaders")) {
    if (e.path().extension() != ".comp" && e.path().extension() != ".glsl") continue;
    std::ifstream in(e.path());
    std::stringstream ss;
    ss << in.rdbuf();
    const std::string src = ss.str();
    const auto all = mutate::Enumerate(e.path().filename().string(), src);
    total += all.size();
    for (const auto& m : all) CHECK(mutate::Apply(src, m) != src);
  }
  CHECK(total > 2000);
  const auto a = mutate::Shuffled(1000, 7), b = mutate::Shuffled(1000, 7), c = mutate::Shuffled(1000, 8);
  CHECK(a == b);
  CHECK(a != c);
  auto sorted = a;
  std::sort(sorted.begin(), sorted.end());
  for (std::size_t i = 0; i < sorted.size(); ++i) CHECK(sorted[i] == i);
  CHECK(mutate::SeedOf("12345") == 12345u);
  CHECK(mutate::SeedOf("a") == 0xAF63DC4C8601EC8Cull);  // FNV-1a's published value for "a"
}

// docs/mutation-survivors.json classifies survivors by id (file:line:column:op:after), which an edit
// elsewhere in the file moves; each entry records its line's text, and `rayspace mutate` applies it
// only while the line still reads so. This test keeps the list current: every entry names a mutant
// the kernels have today, on a line that reads as recorded.
TEST_CASE("mutants: every classified survivor is a mutant of today's kernels, on the line it was classified on") {
  std::ifstream in(test::SourceDir() / "docs" / "mutation-survivors.json");
  REQUIRE(in.good());
  const nlohmann::json list = nlohmann::json::parse(in).at("mutants");
  CHECK(list.size() > 20);
  for (const auto& [id, entry] : list.items()) {
    CAPTURE(id);
    const std::string file = id.substr(0, id.find(':'));
    std::ifstream s(test::SourceDir() / "gpu" / "shaders" / file);
    REQUIRE(s.good());
    std::stringstream ss;
    ss << s.rdbuf();
    const auto all = mutate::Enumerate(file, ss.str());
    const auto it = std::find_if(all.begin(), all.end(), [&](const mutate::Mutation& m) { return m.Id() == id; });
    REQUIRE(it != all.end());
    CHECK(mutate::ClassificationApplies(entry.value("source", std::string()), mutate::LineText(ss.str(), it->line)));
  }
  CHECK(mutate::ClassificationApplies("if (p >= pc.count) return;", "if (p >= pc.count) return;"));
  CHECK_FALSE(mutate::ClassificationApplies("if (p >= pc.count) return;", "const uint p = GlobalIndex();"));
  CHECK_FALSE(mutate::ClassificationApplies("", ""));  // an entry without its line applies nowhere
}
