#include "rayspace/junit.h"

#include <cstdint>

#include <fmt/format.h>

namespace rayspace {
namespace {

constexpr const char* kReplacement = "\xEF\xBF\xBD";  // U+FFFD

// The length of the well-formed UTF-8 sequence XML 1.0 allows at s[i], or 0.
std::size_t CharLength(const std::string& s, std::size_t i) {
  const auto b = static_cast<unsigned char>(s[i]);
  if (b < 0x80) return b >= 0x20 || b == '\t' || b == '\n' || b == '\r' ? 1 : 0;
  const std::size_t n = b >= 0xF0 && b <= 0xF4 ? 4 : b >= 0xE0 ? 3 : b >= 0xC2 && b < 0xE0 ? 2 : 0;
  if (n == 0 || i + n > s.size()) return 0;
  std::uint32_t cp = b & (0x7F >> n);
  for (std::size_t k = 1; k < n; ++k) {
    const auto c = static_cast<unsigned char>(s[i + k]);
    if ((c & 0xC0) != 0x80) return 0;
    cp = cp << 6 | (c & 0x3F);
  }
  const bool overlong = (n == 3 && cp < 0x800) || (n == 4 && cp < 0x10000);
  const bool excluded = (cp >= 0xD800 && cp <= 0xDFFF) || cp == 0xFFFE || cp == 0xFFFF || cp > 0x10FFFF;
  return overlong || excluded ? 0 : n;
}

std::string Escape(const std::string& s) {
  std::string out;
  out.reserve(s.size());
  for (std::size_t i = 0; i < s.size();) {
    const std::size_t n = CharLength(s, i);
    if (n == 0) {
      out += kReplacement;
      ++i;
      continue;
    }
    switch (s[i]) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&apos;"; break;
      case '\n': out += "&#10;"; break;  // kept in attributes, which would otherwise fold it to a space
      case '\r': out += "&#13;"; break;
      case '\t': out += "&#9;"; break;
      default: out.append(s, i, n);
    }
    i += n;
  }
  return out;
}

struct Counts {
  std::size_t tests = 0, failures = 0, errors = 0, skipped = 0;
  double seconds = 0;
  void Add(const JUnitCase& c) {
    ++tests;
    failures += c.outcome == JUnitCase::Outcome::kFailure;
    errors += c.outcome == JUnitCase::Outcome::kError;
    skipped += c.outcome == JUnitCase::Outcome::kSkipped;
    seconds += c.seconds;
  }
  std::string Attributes() const {
    return fmt::format("tests=\"{}\" failures=\"{}\" errors=\"{}\" skipped=\"{}\" time=\"{:.3f}\"", tests, failures, errors, skipped, seconds);
  }
};

std::string CaseXml(const JUnitCase& c) {
  std::string x = fmt::format("    <testcase classname=\"{}\" name=\"{}\" time=\"{:.3f}\"", Escape(c.classname), Escape(c.name), c.seconds);
  std::string body;
  switch (c.outcome) {
    case JUnitCase::Outcome::kPassed: break;
    case JUnitCase::Outcome::kFailure:
    case JUnitCase::Outcome::kError:
      body += fmt::format("      <{0} type=\"{1}\" message=\"{2}\">{3}</{0}>\n", c.outcome == JUnitCase::Outcome::kFailure ? "failure" : "error",
                          Escape(c.type), Escape(c.message), Escape(c.details));
      break;
    case JUnitCase::Outcome::kSkipped: body += fmt::format("      <skipped message=\"{}\"/>\n", Escape(c.message)); break;
  }
  if (!c.output.empty()) body += fmt::format("      <system-out>{}</system-out>\n", Escape(c.output));
  return body.empty() ? x + "/>\n" : x + ">\n" + body + "    </testcase>\n";
}

}  // namespace

std::string JUnitXml(const std::string& name, const std::vector<JUnitSuite>& suites) {
  Counts all;
  std::string body;
  for (const JUnitSuite& s : suites) {
    Counts counts;
    std::string cases;
    for (const JUnitCase& c : s.cases) {
      JUnitCase clamped = c;  // a negative or non-finite time is written as 0: the schema's seconds are >= 0
      if (!(clamped.seconds >= 0 && clamped.seconds < 1e12)) clamped.seconds = 0;
      counts.Add(clamped);
      all.Add(clamped);
      cases += CaseXml(clamped);
    }
    body += fmt::format("  <testsuite name=\"{}\" {}>\n{}  </testsuite>\n", Escape(s.name), counts.Attributes(), cases);
  }
  return fmt::format("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<testsuites name=\"{}\" {}>\n{}</testsuites>\n", Escape(name),
                     all.Attributes(), body);
}

}  // namespace rayspace
