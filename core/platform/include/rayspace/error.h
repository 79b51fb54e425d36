// Errors that leave the program: bad input (exit code 2) and internal failures.
#pragma once
#include <stdexcept>
#include <string>

#include <fmt/format.h>

namespace rayspace {

// Bad user input: a scene, mesh, CLI argument or value out of range. The message is one line that
// names the input (file and line or field) so the user can fix it; the CLI exits with code 2.
class InputError : public std::runtime_error {
 public:
  explicit InputError(const std::string& what) : std::runtime_error(what) {}
};

template <typename... Args>
[[noreturn]] void ThrowInput(fmt::format_string<Args...> f, Args&&... args) {
  throw InputError(fmt::format(f, std::forward<Args>(args)...));
}

// Invariant checks that stay on in release builds: a failure is a bug in rayspace, not bad input.
// By default a failed check aborts (a core dump for the debugger); the CLI asks for a CheckFailure
// exception instead (Settings::check_failures_throw), so a failure ends the run with its one-line message and exit code 1, never a
// signal, and no half-written output stays behind.
class CheckFailure : public std::logic_error {
 public:
  explicit CheckFailure(const std::string& what) : std::logic_error(what) {}
};
[[noreturn]] void CheckFailed(const char* expr, const char* file, int line, const std::string& msg);

}  // namespace rayspace

#define RS_CHECK(cond)                                                      \
  do {                                                                      \
    if (!(cond)) ::rayspace::CheckFailed(#cond, __FILE__, __LINE__, {});    \
  } while (0)
#define RS_CHECK_MSG(cond, ...)                                                                 \
  do {                                                                                          \
    if (!(cond)) ::rayspace::CheckFailed(#cond, __FILE__, __LINE__, fmt::format(__VA_ARGS__));  \
  } while (0)
#ifndef NDEBUG
#define RS_DCHECK(cond) RS_CHECK(cond)
#else
#define RS_DCHECK(cond) \
  do {                  \
  } while (0)
#endif
