// RS_FIELDS: a struct names its fields once, so generic code (the diff's buffer sets, replay) can
// walk them by name without a hand-written list per struct.
//
//   struct PairSlots { std::vector<std::uint8_t> flags; ...; RS_FIELDS(flags, values, tested) };
//
// gives `Tie()` (a tuple of references, const or not) and `kFieldNames` ("flags, values, tested");
// FieldName<S>(i) is the i-th name. RS_NAMED_FIELDS("a, b", x, y) names the fields differently from
// the members (used where saved buffer names predate the member names).
#pragma once
#include <cstddef>
#include <string_view>
#include <tuple>
#include <utility>

#define RS_NAMED_FIELDS(names, ...)                                  \
  static constexpr std::string_view kFieldNames = names;             \
  auto Tie() { return std::tie(__VA_ARGS__); }                       \
  auto Tie() const { return std::tie(__VA_ARGS__); }
#define RS_FIELDS(...) RS_NAMED_FIELDS(#__VA_ARGS__, __VA_ARGS__)

namespace rayspace::emu {

template <typename S>
concept HasFields = requires(const S& s) {
  S::kFieldNames;
  s.Tie();
};

// The i-th comma-separated name of a field list, without spaces.
constexpr std::string_view FieldName(std::string_view names, std::size_t i) {
  for (; i > 0; --i) names.remove_prefix(names.find(',') + 1);
  names = names.substr(0, names.find(','));
  while (!names.empty() && (names.front() == ' ' || names.front() == '\n')) names.remove_prefix(1);
  while (!names.empty() && (names.back() == ' ' || names.back() == '\n')) names.remove_suffix(1);
  return names;
}

constexpr std::size_t FieldCount(std::string_view names) {
  std::size_t n = names.empty() ? 0 : 1;
  for (char c : names) n += c == ',';
  return n;
}

// Calls f(name, field) for every field of s in declaration order.
template <HasFields S, typename F>
void ForEachField(S& s, F&& f) {
  auto fields = s.Tie();
  static_assert(FieldCount(S::kFieldNames) == std::tuple_size_v<decltype(fields)>, "a name for every field");
  [&]<std::size_t... I>(std::index_sequence<I...>) {
    (f(FieldName(S::kFieldNames, I), std::get<I>(fields)), ...);
  }(std::make_index_sequence<std::tuple_size_v<decltype(fields)>>{});
}

}  // namespace rayspace::emu
