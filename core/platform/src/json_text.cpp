#include "rayspace/json_text.h"

#include <cerrno>

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

}  // namespace rayspace
