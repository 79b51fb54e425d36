#include "rayspace/json_text.h"

#include <cerrno>
#include <set>
#include <vector>

#include <fmt/format.h>
#include <iconv.h>

namespace rayspace {
namespace {

// Decoding to UTF-32 rejects exactly what JSON's UTF-8 rejects: stray continuation bytes, overlong
// forms, surrogates, code points beyond U+10FFFF and truncated sequences.
class Utf8Decoder {
 public:
  Utf8Decoder() : cd_(iconv_open("UTF-32LE", "UTF-8")) {}
  ~Utf8Decoder() {
    if (cd_ != reinterpret_cast<iconv_t>(-1)) iconv_close(cd_);
  }
  Utf8Decoder(const Utf8Decoder&) = delete;
  Utf8Decoder& operator=(const Utf8Decoder&) = delete;
  // The length of the valid UTF-8 prefix of `s`.
  std::size_t ValidPrefix(std::string_view s) {
    iconv(cd_, nullptr, nullptr, nullptr, nullptr);
    char* in = const_cast<char*>(s.data());
    std::size_t in_left = s.size();
    char out[1024];
    while (in_left > 0) {
      char* o = out;
      std::size_t out_left = sizeof out;
      if (iconv(cd_, &in, &in_left, &o, &out_left) == static_cast<std::size_t>(-1) && errno != E2BIG) break;
    }
    return s.size() - in_left;
  }

 private:
  iconv_t cd_;
};

Utf8Decoder& Decoder() {
  thread_local Utf8Decoder decoder;
  return decoder;
}

bool Valid(std::string_view s) { return Decoder().ValidPrefix(s) == s.size(); }

bool HasInvalid(const nlohmann::json& j) {
  if (j.is_string()) return !Valid(j.get_ref<const std::string&>());
  if (j.is_object()) {
    for (const auto& [key, value] : j.items())
      if (!Valid(key) || HasInvalid(value)) return true;
  } else if (j.is_array()) {
    for (const nlohmann::json& e : j)
      if (HasInvalid(e)) return true;
  }
  return false;
}

nlohmann::json Escaped(const nlohmann::json& j) {
  if (j.is_string()) return EscapeInvalidUtf8(j.get_ref<const std::string&>());
  if (j.is_array()) {
    nlohmann::json a = nlohmann::json::array();
    for (const nlohmann::json& e : j) a.push_back(Escaped(e));
    return a;
  }
  if (!j.is_object()) return j;
  nlohmann::json o = nlohmann::json::object();
  for (const auto& [key, value] : j.items()) o[EscapeInvalidUtf8(key)] = Escaped(value);
  return o;
}

}  // namespace

std::string EscapeInvalidUtf8(std::string_view s) {
  std::string out;
  while (!s.empty()) {
    const std::size_t valid = Decoder().ValidPrefix(s);
    out.append(s.substr(0, valid));
    if (valid == s.size()) break;
    out += fmt::format("\\x{:02x}", static_cast<unsigned char>(s[valid]));
    s.remove_prefix(valid + 1);
  }
  return out;
}

std::string JsonText(const nlohmann::json& j, int indent) {
  return (HasInvalid(j) ? Escaped(j) : j).dump(indent) + "\n";
}

nlohmann::json ParseJson(std::string_view text) {
  if (const std::size_t nul = text.find('\0'); nul != std::string_view::npos)
    throw JsonError(fmt::format("byte {}: a NUL byte", nul + 1));
  std::vector<std::set<std::string>> keys;  // per open object, the keys it has
  const nlohmann::json::parser_callback_t check = [&keys](int depth, nlohmann::json::parse_event_t event, nlohmann::json& parsed) {
    using E = nlohmann::json::parse_event_t;
    if ((event == E::object_start || event == E::array_start) && depth >= kMaxJsonDepth)
      throw JsonError(fmt::format("nested deeper than {} arrays and objects", kMaxJsonDepth));
    if (event == E::object_start) keys.emplace_back();
    if (event == E::object_end && !keys.empty()) keys.pop_back();
    if (event == E::key && !keys.empty() && !keys.back().insert(parsed.get<std::string>()).second)
      throw JsonError(fmt::format("the key \"{}\" is given twice in one object", EscapeInvalidUtf8(parsed.get<std::string>())));
    return true;
  };
  try {
    return nlohmann::json::parse(text, check);
  } catch (const nlohmann::json::exception& e) {  // syntax errors and number overflow (1e400) alike
    std::string what = e.what();
    if (auto p = what.find("] "); p != std::string::npos) what = what.substr(p + 2);
    if (what.rfind("parse error at ", 0) == 0) what = what.substr(15);
    throw JsonError(what);
  }
}

}  // namespace rayspace
