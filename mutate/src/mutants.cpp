#include "rayspace/mutate/mutants.h"

#include <bit>
#include <limits>

#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <algorithm>
#include <map>
#include <set>

#include <fmt/format.h>

namespace rayspace::mutate {
namespace {

enum class Kind { kIdent, kNumber, kOp };

struct Token {
  Kind kind;
  std::size_t offset;
  std::string text;
  bool in_layout = false;  // inside layout( ... ): qualifiers, not code
};

bool IdentStart(char c) { return std::isalpha(static_cast<unsigned char>(c)) || c == '_'; }
bool IdentChar(char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; }

// The longest operator at s[i].
std::size_t OperatorLength(std::string_view s, std::size_t i) {
  static const char* const kOps[] = {"<<=", ">>=", "<<", ">>", "<=", ">=", "==", "!=", "&&", "||", "^^", "++", "--", "+=", "-=",
                                     "*=",  "/=",  "%=", "&=", "|=", "^="};
  for (const char* op : kOps) {
    const std::string_view o(op);
    if (s.substr(i, o.size()) == o) return o.size();
  }
  return 1;
}

// A number literal from s[i]: digits, a point, an exponent with sign, suffixes, hex digits.
std::size_t NumberLength(std::string_view s, std::size_t i) {
  std::size_t j = i;
  if (s.substr(i, 2) == "0x" || s.substr(i, 2) == "0X") {
    j += 2;
    while (j < s.size() && (std::isxdigit(static_cast<unsigned char>(s[j])))) ++j;
  } else {
    while (j < s.size() && (std::isdigit(static_cast<unsigned char>(s[j])) || s[j] == '.')) ++j;
    if (j < s.size() && (s[j] == 'e' || s[j] == 'E')) {
      ++j;
      if (j < s.size() && (s[j] == '+' || s[j] == '-')) ++j;
      while (j < s.size() && std::isdigit(static_cast<unsigned char>(s[j]))) ++j;
    }
  }
  while (j < s.size() && (s[j] == 'u' || s[j] == 'U' || s[j] == 'f' || s[j] == 'F' || s[j] == 'l' || s[j] == 'L')) ++j;
  return j - i;
}

// The end of a preprocessor line starting at i (continuations with a backslash included).
std::size_t LineEnd(std::string_view s, std::size_t i) {
  while (i < s.size() && s[i] != '\n') {
    if (s[i] == '\\' && i + 1 < s.size() && s[i + 1] == '\n') ++i;
    ++i;
  }
  return i;
}

// Tokens of code: comments and preprocessor directives skipped, except a #define's body (the
// kernels' workgroup macros hold code); a #define's name and parameters are skipped too.
std::vector<Token> Tokenize(std::string_view s) {
  std::vector<Token> out;
  bool line_start = true;
  for (std::size_t i = 0; i < s.size();) {
    const char c = s[i];
    if (c == '\n') {
      line_start = true;
      ++i;
      continue;
    }
    if (std::isspace(static_cast<unsigned char>(c)) || c == '\\') {
      ++i;
      continue;
    }
    if (s.substr(i, 2) == "//") {
      i = s.find('\n', i);
      if (i == std::string_view::npos) break;
      continue;
    }
    if (s.substr(i, 2) == "/*") {
      const std::size_t e = s.find("*/", i + 2);
      i = e == std::string_view::npos ? s.size() : e + 2;
      continue;
    }
    if (c == '#' && line_start) {
      std::size_t j = i + 1;
      while (j < s.size() && (s[j] == ' ' || s[j] == '\t')) ++j;
      if (s.substr(j, 6) != "define") {
        i = LineEnd(s, i);
        continue;
      }
      j += 6;
      while (j < s.size() && (s[j] == ' ' || s[j] == '\t')) ++j;
      while (j < s.size() && IdentChar(s[j])) ++j;
      if (j < s.size() && s[j] == '(') j = s.find(')', j) + 1;  // the macro's parameters
      i = j;
      line_start = false;
      continue;
    }
    line_start = false;
    if (IdentStart(c)) {
      std::size_t j = i;
      while (j < s.size() && IdentChar(s[j])) ++j;
      out.push_back({Kind::kIdent, i, std::string(s.substr(i, j - i))});
      i = j;
    } else if (std::isdigit(static_cast<unsigned char>(c)) || (c == '.' && i + 1 < s.size() && std::isdigit(static_cast<unsigned char>(s[i + 1])))) {
      const std::size_t n = NumberLength(s, i);
      out.push_back({Kind::kNumber, i, std::string(s.substr(i, n))});
      i += n;
    } else {
      const std::size_t n = OperatorLength(s, i);
      out.push_back({Kind::kOp, i, std::string(s.substr(i, n))});
      i += n;
    }
  }
  // Mark layout( ... ).
  for (std::size_t k = 0; k + 1 < out.size(); ++k) {
    if (out[k].text != "layout" || out[k + 1].text != "(") continue;
    int depth = 0;
    for (std::size_t m = k + 1; m < out.size(); ++m) {
      depth += out[m].text == "(" ? 1 : out[m].text == ")" ? -1 : 0;
      out[m].in_layout = true;
      if (depth == 0) break;
    }
  }
  return out;
}

// Whether the token before k ends an operand (so +, - at k are binary).
bool EndsOperand(const std::vector<Token>& t, std::size_t k) {
  if (k == 0) return false;
  const Token& p = t[k - 1];
  return p.kind != Kind::kOp || p.text == ")" || p.text == "]";
}

std::string IntegerPlus(const std::string& text, long delta, bool& ok) {
  const bool hex = text.size() > 2 && text[0] == '0' && (text[1] == 'x' || text[1] == 'X');
  std::size_t digits = hex ? 2 : 0;
  while (digits < text.size() && (hex ? std::isxdigit(static_cast<unsigned char>(text[digits])) : std::isdigit(static_cast<unsigned char>(text[digits]))))
    ++digits;
  const std::string body = text.substr(hex ? 2 : 0, digits - (hex ? 2 : 0)), suffix = text.substr(digits);
  const unsigned long long v = std::strtoull(body.c_str(), nullptr, hex ? 16 : 10);
  ok = !body.empty() && !(delta < 0 && v == 0) && v < (1ull << 31);
  if (!ok) return {};
  const unsigned long long w = delta < 0 ? v - 1 : v + 1;
  return (hex ? fmt::format("0x{:X}", w) : std::to_string(w)) + suffix;
}

// One float ulp up, printed so that it reads back as that float. A subnormal is written as its bit
// pattern: lavapipe compares with a subnormal literal as with 0 (0.0 one ulp up, spelled
// 1.40129846e-45, changed nothing where uintBitsToFloat(1u) did), which would make the mutant a no-op.
std::string FloatUlpUp(const std::string& text, bool& ok) {
  std::string body = text;
  const bool f_suffix = !body.empty() && (body.back() == 'f' || body.back() == 'F');
  if (f_suffix) body.pop_back();
  const float v = std::strtof(body.c_str(), nullptr);
  ok = std::isfinite(v);
  if (!ok) return {};
  const float w = std::nextafter(v, INFINITY);
  if (w != 0.0f && std::fabs(w) < std::numeric_limits<float>::min())
    return fmt::format("uintBitsToFloat(0x{:08X}u)", std::bit_cast<std::uint32_t>(w));
  std::string out = fmt::format("{:.9g}", w);
  if (out.find_first_of(".eE") == std::string::npos) out += ".0";
  return out + (f_suffix ? "f" : "");
}

bool IsFloatLiteral(const std::string& t) {
  if (t.size() > 1 && (t[1] == 'x' || t[1] == 'X')) return false;
  return t.find_first_of(".eE") != std::string::npos || t.back() == 'f' || t.back() == 'F';
}

// (line, column) of an offset, 1-based.
void Position(std::string_view s, std::size_t offset, int& line, int& column) {
  line = 1;
  std::size_t start = 0;
  for (std::size_t i = 0; i < offset && i < s.size(); ++i)
    if (s[i] == '\n') ++line, start = i + 1;
  column = static_cast<int>(offset - start) + 1;
}

struct Builder {
  std::string_view file, source;
  std::vector<Mutation> out;
  void Add(std::string_view op, std::size_t offset, std::size_t length, std::string after) {
    Mutation m;
    m.file = std::string(file);
    m.op = std::string(op);
    m.offset = offset;
    m.length = length;
    m.before = std::string(source.substr(offset, length));
    m.after = std::move(after);
    Position(source, offset, m.line, m.column);
    out.push_back(std::move(m));
  }
};

void AddOperators(Builder& b, const std::vector<Token>& t, std::size_t k) {
  static const std::map<std::string, std::string> kCompare = {{"<", "<="}, {"<=", "<"}, {">", ">="}, {">=", ">"}, {"==", "!="}, {"!=", "=="}};
  static const std::map<std::string, std::string> kArith = {{"+", "-"},   {"-", "+"},   {"*", "/"},   {"/", "*"},  {"+=", "-="},
                                                            {"-=", "+="}, {"*=", "/="}, {"/=", "*="}, {"&&", "||"}, {"||", "&&"},
                                                            {"&", "|"},   {"|", "&"}};
  const Token& tok = t[k];
  if (const auto it = kCompare.find(tok.text); it != kCompare.end()) {
    b.Add(kComparison, tok.offset, tok.text.size(), it->second);
    return;
  }
  const auto it = kArith.find(tok.text);
  if (it == kArith.end()) return;
  const bool unary_possible = tok.text == "+" || tok.text == "-";
  if (unary_possible && !EndsOperand(t, k)) return;
  b.Add(kArithmetic, tok.offset, tok.text.size(), it->second);
}

void AddLiteral(Builder& b, const Token& tok) {
  bool ok = false;
  if (IsFloatLiteral(tok.text)) {
    const std::string up = FloatUlpUp(tok.text, ok);
    if (ok) b.Add(kFloatUlp, tok.offset, tok.text.size(), up);
    return;
  }
  for (const long delta : {1L, -1L}) {
    const std::string v = IntegerPlus(tok.text, delta, ok);
    if (ok) b.Add(kConstant, tok.offset, tok.text.size(), v);
  }
}

// for ( init ; cond ; step ): the condition's bound, the text after its comparison, +1 and -1.
void AddLoopBound(Builder& b, const std::vector<Token>& t, std::size_t k) {
  if (t[k].text != "for" || k + 1 >= t.size() || t[k + 1].text != "(") return;
  std::size_t m = k + 2, semis = 0;
  int depth = 0;
  std::size_t cmp = 0, end = 0;
  for (; m < t.size(); ++m) {
    const std::string& x = t[m].text;
    if (x == "(") ++depth;
    if (x == ")") {
      if (depth == 0) break;
      --depth;
    }
    if (x == ";" && depth == 0 && ++semis == 2) {
      end = m;
      break;
    }
    if (semis == 1 && depth == 0 && (x == "<" || x == "<=" || x == ">" || x == ">=") && cmp == 0) cmp = m;
  }
  if (!cmp || !end || cmp + 1 >= end) return;
  const std::size_t from = t[cmp + 1].offset, to = t[end].offset;
  std::string rhs(b.source.substr(from, to - from));
  while (!rhs.empty() && std::isspace(static_cast<unsigned char>(rhs.back()))) rhs.pop_back();
  b.Add(kLoopBound, from, rhs.size(), "(" + rhs + ") + 1");
  b.Add(kLoopBound, from, rhs.size(), "(" + rhs + ") - 1");
}

}  // namespace

std::string Mutation::Id() const { return fmt::format("{}:{}:{}:{}:{}", file, line, column, op, after); }

std::vector<Mutation> Enumerate(std::string_view file, std::string_view source) {
  const std::vector<Token> t = Tokenize(source);
  Builder b{file, source, {}};
  // The kernel's bindings, in order of declaration (for the binding swap).
  std::vector<std::size_t> bindings;
  for (std::size_t k = 0; k + 2 < t.size(); ++k)
    if (t[k].in_layout && t[k].text == "binding" && t[k + 1].text == "=") bindings.push_back(k + 2);
  static const std::set<std::string> kBarriers = {"barrier", "memoryBarrier", "memoryBarrierShared", "memoryBarrierBuffer", "groupMemoryBarrier",
                                                  "subgroupBarrier", "subgroupMemoryBarrier", "subgroupMemoryBarrierShared"};
  for (std::size_t k = 0; k < t.size(); ++k) {
    const Token& tok = t[k];
    if (tok.in_layout) continue;
    if (tok.kind == Kind::kOp) {
      AddOperators(b, t, k);
      if (tok.text == "." && k + 1 < t.size() && EndsOperand(t, k) && t[k + 1].text.size() == 1) {
        static const std::map<std::string, std::string> kSwap = {{"x", "y"}, {"y", "z"}, {"z", "x"}, {"w", "x"}};
        if (const auto it = kSwap.find(t[k + 1].text); it != kSwap.end()) b.Add(kComponent, t[k + 1].offset, 1, it->second);
      }
    } else if (tok.kind == Kind::kNumber) {
      // The planted faults' numbers (kFault == N) select test scaffolding, not the kernel's work.
      const bool fault_number = k >= 2 && t[k - 2].text == "kFault" && (t[k - 1].text == "==" || t[k - 1].text == "!=");
      if (!fault_number) AddLiteral(b, tok);
    } else if (kBarriers.count(tok.text) && k + 2 < t.size() && t[k + 1].text == "(" && t[k + 2].text == ")") {
      b.Add(kBarrier, tok.offset, t[k + 2].offset + 1 - tok.offset, "");
    } else {
      AddLoopBound(b, t, k);
    }
  }
  // Each buffer's binding swapped with the next declared one's (a different constant): both
  // declarations change, so the kernel still declares each binding once.
  for (std::size_t i = 0; i + 1 < bindings.size(); ++i) {
    const Token &x = t[bindings[i]], &y = t[bindings[i + 1]];
    if (x.text == y.text) continue;
    b.Add(kBinding, x.offset, x.text.size(), y.text);
    Mutation& m = b.out.back();
    m.offset2 = y.offset;
    m.length2 = y.text.size();
    m.after2 = x.text;
  }
  std::stable_sort(b.out.begin(), b.out.end(), [](const Mutation& x, const Mutation& y) { return x.offset < y.offset; });
  return b.out;
}

std::string Apply(std::string_view source, const Mutation& m) {
  std::string s(source);
  if (m.length2 > 0) s.replace(m.offset2, m.length2, m.after2);  // after the first edit: offsets hold
  return s.replace(m.offset, m.length, m.after);
}

std::vector<std::string> Includes(std::string_view source) {
  std::vector<std::string> out;
  std::size_t i = 0;
  while ((i = source.find("#include", i)) != std::string_view::npos) {
    const std::size_t a = source.find('"', i), nl = source.find('\n', i);
    if (a != std::string_view::npos && a < nl) {
      const std::size_t e = source.find('"', a + 1);
      if (e != std::string_view::npos && e < nl) out.emplace_back(source.substr(a + 1, e - a - 1));
    }
    i += 8;
  }
  return out;
}

bool ClassificationApplies(std::string_view recorded_source, std::string_view current_source) {
  return !recorded_source.empty() && recorded_source == current_source;
}

std::string LineText(std::string_view source, int line) {
  std::size_t start = 0;
  for (int l = 1; l < line && start != std::string_view::npos; ++l) {
    start = source.find('\n', start);
    if (start != std::string_view::npos) ++start;
  }
  if (start == std::string_view::npos || start > source.size()) return {};
  std::size_t end = source.find('\n', start);
  std::string text(source.substr(start, end == std::string_view::npos ? std::string_view::npos : end - start));
  const std::size_t first = text.find_first_not_of(" \t");
  return first == std::string::npos ? std::string() : text.substr(first);
}

std::vector<std::size_t> Shuffled(std::size_t count, std::uint64_t seed) {
  std::vector<std::size_t> order(count);
  for (std::size_t i = 0; i < count; ++i) order[i] = i;
  std::uint64_t state = seed;
  const auto next = [&] {
    std::uint64_t z = (state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  };
  for (std::size_t i = count; i > 1; --i) std::swap(order[i - 1], order[next() % i]);
  return order;
}

std::uint64_t SeedOf(std::string_view text) {
  if (!text.empty() && text.find_first_not_of("0123456789") == std::string_view::npos && text.size() < 19)
    return std::strtoull(std::string(text).c_str(), nullptr, 10);
  std::uint64_t h = 0xCBF29CE484222325ull;
  for (const char c : text) h = (h ^ static_cast<unsigned char>(c)) * 0x100000001B3ull;
  return h;
}

}  // namespace rayspace::mutate
