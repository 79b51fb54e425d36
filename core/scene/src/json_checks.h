// Checked readers for JSON input, shared by the scene loader and the procedural generators' params:
// each either returns the value or throws a one-line InputError "FILE: FIELD: what is wrong", the
// wrong value shown. Internal to rayspace_core.
#pragma once
#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <string>

#include <fmt/format.h>
#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include "rayspace/error.h"

namespace rayspace::json_checks {

using nlohmann::json;

// Where the input comes from: the scene file (and, for generators, the object and generator).
struct Ctx {
  std::string file;
  [[noreturn]] void Fail(const std::string& field, const std::string& msg) const {
    ThrowInput("{}: {}: {}", file, field, msg);
  }
};

// A JSON value as written, cut to 40 characters.
inline std::string Shown(const json& v) {
  std::string s = v.dump();
  if (s.size() > 40) s = s.substr(0, 37) + "...";
  return s;
}

// `j` must be an object whose keys are among `allowed`; an unknown key is named with the known ones.
inline void CheckKeys(const Ctx& c, const json& j, const std::string& field, std::initializer_list<const char*> allowed) {
  if (!j.is_object()) c.Fail(field, fmt::format("expected an object, got {}", Shown(j)));
  for (auto it = j.begin(); it != j.end(); ++it) {
    bool ok = false;
    for (const char* a : allowed) ok |= it.key() == a;
    if (ok) continue;
    std::string known;
    for (const char* a : allowed) known += (known.empty() ? "" : ", ") + std::string(a);
    c.Fail(field + "." + it.key(), fmt::format("unknown key (known: {})", known.empty() ? "none" : known));
  }
}

// A finite number in [lo, hi], or in (lo, hi] when `above_lo`.
inline double Number(const Ctx& c, const json& j, const std::string& field, double lo, double hi, bool above_lo = false) {
  if (!j.is_number()) c.Fail(field, fmt::format("expected a number, got {}", Shown(j)));
  const double v = j.get<double>();
  if (!std::isfinite(v)) c.Fail(field, fmt::format("{} is not finite", v));
  if (above_lo ? !(v > lo) || v > hi : v < lo || v > hi)
    c.Fail(field, fmt::format("{} out of range {}{}, {}]", v, above_lo ? "(" : "[", lo, hi));
  return v;
}

// An integer in [lo, hi], written as a JSON integer (or, when `integral_float`, also as a float
// with an integral value: 8.0).
inline int Integer(const Ctx& c, const json& j, const std::string& field, long long lo, long long hi,
                   bool integral_float = false) {
  if (j.is_number_unsigned() && j.get<std::uint64_t>() > static_cast<std::uint64_t>(hi))
    c.Fail(field, fmt::format("{} out of range [{}, {}]", j.get<std::uint64_t>(), lo, hi));
  long long v = 0;
  if (j.is_number_integer()) {
    v = j.get<long long>();
  } else if (integral_float && j.is_number_float()) {
    const double d = j.get<double>();
    if (!std::isfinite(d)) c.Fail(field, fmt::format("{} is not finite", d));
    if (d != std::floor(d)) c.Fail(field, fmt::format("expected an integer, got {}", Shown(j)));
    if (d < static_cast<double>(lo) || d > static_cast<double>(hi))
      c.Fail(field, fmt::format("{} out of range [{}, {}]", d, lo, hi));
    v = static_cast<long long>(d);
  } else {
    c.Fail(field, fmt::format("expected an integer, got {}", Shown(j)));
  }
  if (v < lo || v > hi) c.Fail(field, fmt::format("{} out of range [{}, {}]", v, lo, hi));
  return static_cast<int>(v);
}

// An array of 3 numbers, each as Number().
inline glm::vec3 Vec3(const Ctx& c, const json& j, const std::string& field, double lo = -1e30, double hi = 1e30,
                      bool above_lo = false) {
  if (!j.is_array() || j.size() != 3) c.Fail(field, fmt::format("expected an array of 3 numbers, got {}", Shown(j)));
  return {static_cast<float>(Number(c, j[0], field + "[0]", lo, hi, above_lo)),
          static_cast<float>(Number(c, j[1], field + "[1]", lo, hi, above_lo)),
          static_cast<float>(Number(c, j[2], field + "[2]", lo, hi, above_lo))};
}

inline bool Bool(const Ctx& c, const json& j, const std::string& field) {
  if (!j.is_boolean()) c.Fail(field, fmt::format("expected true or false, got {}", Shown(j)));
  return j.get<bool>();
}

inline const std::string& String(const Ctx& c, const json& j, const std::string& field, const char* what = "a string") {
  if (!j.is_string()) c.Fail(field, fmt::format("expected {}, got {}", what, Shown(j)));
  return j.get_ref<const std::string&>();
}

inline const json& Required(const Ctx& c, const json& j, const char* key, const std::string& field) {
  auto it = j.find(key);
  if (it == j.end()) c.Fail(field.empty() ? key : field + "." + key, "missing");
  return *it;
}

}  // namespace rayspace::json_checks
