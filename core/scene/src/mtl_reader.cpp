#include "mtl_reader.h"

#include <cmath>
#include <istream>
#include <string_view>

#include "obj_text.h"
#include "rayspace/error.h"
#include "rayspace/input_file.h"

namespace rayspace {
namespace {

// The keys tinyobjloader reads as numbers, with how many values and the accepted range. Kd, Ks and
// Ns feed a material (docs/scene-format.md, "OBJ and MTL"), with the ranges of the scene's own
// `diffuse`, `specular` and `shininess`; the others are ignored but still checked, since a NaN or a
// negative colour there is a broken file all the same.
struct MtlKey {
  std::string_view key;
  int values;
  double lo, hi;
  bool integer;
};
constexpr MtlKey kMtlKeys[] = {
    {"Kd", 3, 0, 1e6, false}, {"Ks", 3, 0, 1e6, false},  {"Ka", 3, 0, 1e6, false}, {"Ke", 3, 0, 1e6, false},
    {"Kt", 3, 0, 1e6, false}, {"Tf", 3, 0, 1e6, false},  {"Ns", 1, 0, 4096, false}, {"Ni", 1, 0, 100, false},
    {"d", 1, 0, 1, false},    {"Tr", 1, 0, 1, false},    {"illum", 1, 0, 10, true},
};

// A number as tinyobjloader reads it (a leading '+' allowed), or nothing.
bool MtlNumber(std::string_view token, double& v) {
  if (token.size() > 1 && token[0] == '+' && token[1] != '-' && token[1] != '+') token.remove_prefix(1);
  return obj_text::ParseFloat(token, v);
}

void CheckValues(const std::string& file, std::size_t line, const MtlKey& k, const std::vector<std::string_view>& tok) {
  const int got = static_cast<int>(tok.size()) - 1;
  if (got != k.values)
    ThrowInput("{}:{}: {} needs {} {}, got {}", file, line, k.key, k.values, k.values == 3 ? "numbers (r g b)" : "number",
               got);
  for (int i = 1; i <= k.values; ++i) {
    double v;
    if (!MtlNumber(tok[i], v)) ThrowInput("{}:{}: {}: '{}' is not a number", file, line, k.key, tok[i]);
    if (!std::isfinite(v)) ThrowInput("{}:{}: {}: '{}' is not finite", file, line, k.key, tok[i]);
    if (v < k.lo || v > k.hi) ThrowInput("{}:{}: {}: {} out of range [{}, {}]", file, line, k.key, tok[i], k.lo, k.hi);
    if (k.integer && v != std::floor(v)) ThrowInput("{}:{}: {}: {} is not an integer", file, line, k.key, tok[i]);
  }
}

// What tinyobjloader made of the values rayspace uses must still be in range: a second line of
// defence should the check and the parser ever read a line differently.
void CheckParsed(const std::string& file, const tinyobj::material_t& m) {
  for (int i = 0; i < 3; ++i) {
    if (!(m.diffuse[i] >= 0 && m.diffuse[i] <= 1e6) || !(m.specular[i] >= 0 && m.specular[i] <= 1e6))
      ThrowInput("{}: material '{}': Kd or Ks out of range [0, 1e6] as parsed", file, m.name);
  }
  if (!(m.shininess >= 0 && m.shininess <= 4096))
    ThrowInput("{}: material '{}': Ns out of range [0, 4096] as parsed", file, m.name);
}

}  // namespace

void ValidateMtlText(const std::string& file, const std::string& text) {
  obj_text::ForEachLine(text, [&](std::size_t line, std::string_view text_line) {
    const auto tok = obj_text::Tokens(text_line);
    if (tok.empty()) return;
    for (const MtlKey& k : kMtlKeys)
      if (tok[0] == k.key) CheckValues(file, line, k, tok);
  });
}

MtlFiles::MtlFiles(const std::filesystem::path& obj)
    : dir_(obj.parent_path()), what_(fmt::format("material file (mtllib of {})", obj.filename().string())) {}

bool MtlFiles::operator()(const std::string& name, std::vector<tinyobj::material_t>* materials,
                          std::map<std::string, int>* by_name, std::string* warn, std::string* err) {
  const std::filesystem::path path = dir_ / name;
  if (std::error_code ec; !std::filesystem::exists(path, ec)) {
    if (warn) *warn += fmt::format("material file '{}' not found (looked at {})\n", name, path.string());
    return false;
  }
  std::string text = ReadInputFile(path, {what_, kMaxTextFileBytes});
  obj_text::NormaliseLineEnds(text, path.string());
  ValidateMtlText(path.string(), text);
  obj_text::TextBuf buf(text);
  std::istream in(&buf);
  const std::size_t before = materials->size();
  tinyobj::LoadMtl(by_name, materials, &in, warn, err);
  for (std::size_t i = before; i < materials->size(); ++i) CheckParsed(path.string(), (*materials)[i]);
  return true;
}

}  // namespace rayspace
