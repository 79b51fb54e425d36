// JUnit XML, the test report CI systems read: `diff`, `mutate` and `reproduce` write one with
// --junit FILE. The layout is docs/schemas/junit.xsd (the Ant JUnit format); JUnitXml writes nothing
// outside it.
#pragma once
#include <string>
#include <vector>

namespace rayspace {

struct JUnitCase {
  enum class Outcome { kPassed, kFailure, kError, kSkipped };
  std::string classname;  // the group, e.g. "diff.reduce"
  std::string name;       // the case, e.g. "reduce.L2.shadow.b0"
  double seconds = 0;
  Outcome outcome = Outcome::kPassed;
  std::string type;     // failure or error: its kind, e.g. "divergence"
  std::string message;  // failure, error or skipped: one line
  std::string details;  // failure or error: the text under it (may span lines)
  std::string output;   // system-out ("" for none)
};

struct JUnitSuite {
  std::string name;
  std::vector<JUnitCase> cases;
};

// The document: <testsuites name=...> holding each suite with its counts and times. Text is escaped,
// and characters XML 1.0 cannot hold (control characters, invalid UTF-8) become U+FFFD.
std::string JUnitXml(const std::string& name, const std::vector<JUnitSuite>& suites);

}  // namespace rayspace
