// PLY mesh loader: a small strict parser for the ascii and binary PLY 1.0 formats.
//
// The PLY readers of CGAL and Assimp accept malformed files, misread them, give no location and
// size allocations from unchecked counts (docs/scene-format.md, "Why PLY is read by rayspace's own
// parser", has the cases), so the format is parsed here. Meshes are user input and the
// loader is fuzzed, so the parser trusts nothing in the file: every count is checked against the
// bytes actually present before it sizes an allocation or a loop, every read is bounds-checked,
// and every failure is an InputError with a one-line message naming the file and the header line,
// the ascii body line and/or the element item ("face 12") where the problem is.
#include <bit>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <system_error>
#include <utility>
#include <vector>

#include "rayspace/error.h"
#include "rayspace/input_file.h"
#include "rayspace/scene.h"

namespace rayspace {
namespace {

static_assert(std::endian::native == std::endian::little || std::endian::native == std::endian::big,
              "binary PLY decoding assumes a little- or big-endian host");

enum class Format { kAscii, kBinaryLittle, kBinaryBig };

enum class Type : std::uint8_t { kInt8, kUInt8, kInt16, kUInt16, kInt32, kUInt32, kFloat32, kFloat64 };

// Both the original PLY type names and the sized aliases later writers use.
struct TypeName {
  std::string_view name;
  Type type;
};
constexpr TypeName kTypeNames[] = {
    {"char", Type::kInt8},      {"uchar", Type::kUInt8},    {"short", Type::kInt16},
    {"ushort", Type::kUInt16},  {"int", Type::kInt32},      {"uint", Type::kUInt32},
    {"float", Type::kFloat32},  {"double", Type::kFloat64}, {"int8", Type::kInt8},
    {"uint8", Type::kUInt8},    {"int16", Type::kInt16},    {"uint16", Type::kUInt16},
    {"int32", Type::kInt32},    {"uint32", Type::kUInt32},  {"float32", Type::kFloat32},
    {"float64", Type::kFloat64},
};

std::optional<Type> ParseType(std::string_view name) {
  for (const TypeName& t : kTypeNames) {
    if (t.name == name) return t.type;
  }
  return std::nullopt;
}

std::string_view NameOf(Type type) {
  for (const TypeName& t : kTypeNames) {
    if (t.type == type) return t.name;
  }
  return "?";
}

std::size_t SizeOf(Type type) {
  switch (type) {
    case Type::kInt8:
    case Type::kUInt8: return 1;
    case Type::kInt16:
    case Type::kUInt16: return 2;
    case Type::kInt32:
    case Type::kUInt32:
    case Type::kFloat32: return 4;
    case Type::kFloat64: return 8;
  }
  return 8;  // not reached: every enumerator is handled above
}

bool IsInteger(Type type) { return type != Type::kFloat32 && type != Type::kFloat64; }

// Range of an integer type, for checking ascii values (binary values fit by construction).
std::pair<std::int64_t, std::int64_t> RangeOf(Type type) {
  switch (type) {
    case Type::kInt8: return {INT8_MIN, INT8_MAX};
    case Type::kUInt8: return {0, UINT8_MAX};
    case Type::kInt16: return {INT16_MIN, INT16_MAX};
    case Type::kUInt16: return {0, UINT16_MAX};
    case Type::kInt32: return {INT32_MIN, INT32_MAX};
    case Type::kUInt32: return {0, UINT32_MAX};
    case Type::kFloat32:
    case Type::kFloat64: break;
  }
  return {0, 0};
}

bool IsSpace(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v'; }

// Text taken from the file, made safe to put in a one-line message: a fuzzed file can hold
// newlines, control bytes or a megabyte-long "token".
std::string Printable(std::string_view s) {
  constexpr std::size_t kMaxLength = 40;
  std::string out;
  for (std::size_t i = 0; i < s.size() && i < kMaxLength; ++i) {
    const auto c = static_cast<unsigned char>(s[i]);
    out += (c >= 0x20 && c < 0x7f) ? static_cast<char>(c) : '?';
  }
  if (s.size() > kMaxLength) out += "...";
  return out;
}

template <typename U>
U ByteSwap(U v) {
  U r = 0;
  for (std::size_t i = 0; i < sizeof(U); ++i) {
    r = static_cast<U>((r << 8) | (v & 0xff));
    v = static_cast<U>(v >> 8);
  }
  return r;
}

struct Property {
  std::string name;
  bool is_list = false;
  Type count_type = Type::kUInt8;  // lists only
  Type type = Type::kFloat32;      // the scalar type, or a list's item type
};

struct Element {
  std::string name;
  std::uint64_t count = 0;
  std::vector<Property> properties;
  int line = 0;  // the header line declaring it, for errors found once the header is done
};

// What each vertex property feeds; the values index the position/normal components.
enum Role : int { kNone = -1, kX = 0, kY, kZ, kNx, kNy, kNz };

class PlyParser {
 public:
  PlyParser(const std::filesystem::path& path, std::string_view data)
      : path_(path), file_(path.string()), data_(data) {}

  MeshData Parse() {
    ParseHeader();
    ResolveElements();
    CheckCountsAgainstSize();
    switch (format_) {
      case Format::kAscii: ParseBody<Format::kAscii>(); break;
      case Format::kBinaryLittle: ParseBody<Format::kBinaryLittle>(); break;
      case Format::kBinaryBig: ParseBody<Format::kBinaryBig>(); break;
    }
    return BuildMesh();
  }

 private:
  // Throws the InputError for the current location (header line, ascii body line, element item).
  template <typename... Args>
  [[noreturn]] void Fail(fmt::format_string<Args...> f, Args&&... args) const {
    std::string where;
    if (line_ > 0) where += fmt::format("line {}: ", line_);
    if (element_ != nullptr) where += fmt::format("{} {}: ", Printable(element_->name), index_);
    ThrowInput("{}: {}{}", file_, where, fmt::format(f, std::forward<Args>(args)...));
  }

  // ---- Header ----

  void ParseHeader() {
    std::size_t pos = 0;
    int line = 0;
    bool have_format = false;
    for (;;) {
      if (pos >= data_.size()) {
        if (line == 0) Fail("not a PLY file (empty)");
        line_ = line;
        Fail("header has no end_header line");
      }
      const std::size_t eol = data_.find('\n', pos);
      const std::size_t end = eol == std::string_view::npos ? data_.size() : eol;
      std::string_view text = data_.substr(pos, end - pos);
      pos = eol == std::string_view::npos ? data_.size() : eol + 1;
      line_ = ++line;

      if (line == 1) {
        // The magic is checked byte for byte (allowing a CRLF writer) so that arbitrary files are
        // refused up front instead of producing a confusing header error further on.
        if (!text.empty() && text.back() == '\r') text.remove_suffix(1);
        if (text != "ply") Fail("not a PLY file (first line is not 'ply')");
        continue;
      }

      // Split into at most kMaxFields fields; more than that is an error for every keyword that
      // checks its field count, and comments do not care.
      constexpr std::size_t kMaxFields = 6;
      std::string_view f[kMaxFields];
      std::size_t n = 0;
      for (std::size_t i = 0; i < text.size() && n < kMaxFields;) {
        while (i < text.size() && IsSpace(text[i])) ++i;
        const std::size_t start = i;
        while (i < text.size() && !IsSpace(text[i])) ++i;
        if (i > start) f[n++] = text.substr(start, i - start);
      }
      if (n == 0) continue;  // blank line: harmless, so tolerated

      const std::string_view keyword = f[0];
      if (keyword == "comment" || keyword == "obj_info") continue;
      if (keyword == "format") {
        FormatLine(f, n, have_format);
        have_format = true;
      } else if (keyword == "element") {
        if (!have_format) Fail("element before the format line");
        ElementLine(f, n, line);
      } else if (keyword == "property") {
        PropertyLine(f, n);
      } else if (keyword == "end_header") {
        if (n != 1) Fail("unexpected text after end_header");
        if (!have_format) Fail("header has no format line");
        body_offset_ = pos;
        header_lines_ = line;
        line_ = 0;
        return;
      } else {
        Fail("unknown header keyword '{}'", Printable(keyword));
      }
    }
  }

  // Header lines split into fields: f[0] is the keyword, n the number of fields (at most 6).
  void FormatLine(const std::string_view* f, std::size_t n, bool have_format) {
    if (have_format) Fail("second format line");
    if (!elements_.empty()) Fail("format line after the first element");
    if (n != 3) Fail("format line must be 'format TYPE 1.0'");
    if (f[1] == "ascii") {
      format_ = Format::kAscii;
    } else if (f[1] == "binary_little_endian") {
      format_ = Format::kBinaryLittle;
    } else if (f[1] == "binary_big_endian") {
      format_ = Format::kBinaryBig;
    } else {
      Fail("unsupported format '{}'", Printable(f[1]));
    }
    if (f[2] != "1.0") Fail("unsupported PLY version '{}' (only 1.0 is supported)", Printable(f[2]));
  }

  void ElementLine(const std::string_view* f, std::size_t n, int line) {
    if (n != 3) Fail("element line must be 'element NAME COUNT'");
    Element e;
    e.name = std::string(f[1]);
    e.line = line;
    const char* first = f[2].data();
    const char* last = first + f[2].size();
    const auto r = std::from_chars(first, last, e.count);
    if (r.ec != std::errc() || r.ptr != last) {
      Fail("bad count '{}' for element '{}'", Printable(f[2]), Printable(f[1]));
    }
    elements_.push_back(std::move(e));
  }

  void PropertyLine(const std::string_view* f, std::size_t n) {
    if (elements_.empty()) Fail("property before any element");
    Property p;
    if (n >= 2 && f[1] == "list") {
      if (n != 5) Fail("list property line must be 'property list COUNT_TYPE ITEM_TYPE NAME'");
      p.is_list = true;
      p.count_type = ParseTypeOrFail(f[2]);
      if (!IsInteger(p.count_type)) {
        Fail("list count type must be an integer type, not '{}'", NameOf(p.count_type));
      }
      p.type = ParseTypeOrFail(f[3]);
      p.name = std::string(f[4]);
    } else {
      if (n != 3) Fail("property line must be 'property TYPE NAME'");
      p.type = ParseTypeOrFail(f[1]);
      p.name = std::string(f[2]);
    }
    for (const Property& other : elements_.back().properties) {
      if (other.name == p.name) Fail("duplicate property '{}'", Printable(p.name));
    }
    elements_.back().properties.push_back(std::move(p));
  }

  Type ParseTypeOrFail(std::string_view name) const {
    const std::optional<Type> t = ParseType(name);
    if (!t) Fail("unknown property type '{}'", Printable(name));
    return *t;
  }

  // Finds the vertex and face elements and the properties the mesh is built from.
  void ResolveElements() {
    for (const Element& e : elements_) {
      const Element** slot = e.name == "vertex" ? &vertex_ : e.name == "face" ? &face_ : nullptr;
      if (slot == nullptr) continue;
      if (*slot != nullptr) {
        line_ = e.line;
        Fail("second '{}' element", e.name);
      }
      *slot = &e;
    }
    if (vertex_ == nullptr) Fail("no vertex element");
    if (face_ == nullptr) Fail("no face element");

    line_ = vertex_->line;
    constexpr std::string_view kRoleNames[] = {"x", "y", "z", "nx", "ny", "nz"};
    bool found[6] = {};
    vertex_roles_.assign(vertex_->properties.size(), kNone);
    for (std::size_t i = 0; i < vertex_->properties.size(); ++i) {
      const Property& p = vertex_->properties[i];
      for (int r = 0; r < 6; ++r) {
        if (p.name != kRoleNames[r]) continue;
        if (p.is_list) Fail("vertex property '{}' must not be a list", p.name);
        vertex_roles_[i] = r;
        found[r] = true;
      }
    }
    for (int r = kX; r <= kZ; ++r) {
      if (!found[r]) Fail("vertex element has no '{}' property", kRoleNames[r]);
    }
    // Normals are all or nothing: a partial set cannot be used, so it is skipped like any other
    // unknown property.
    has_normals_ = found[kNx] && found[kNy] && found[kNz];
    if (!has_normals_) {
      for (int& role : vertex_roles_) {
        if (role >= kNx) role = kNone;
      }
    }

    line_ = face_->line;
    for (std::string_view name : {"vertex_indices", "vertex_index"}) {
      for (std::size_t i = 0; i < face_->properties.size() && face_indices_ < 0; ++i) {
        if (face_->properties[i].name == name) face_indices_ = static_cast<int>(i);
      }
    }
    if (face_indices_ < 0) Fail("face element has no 'vertex_indices' list property");
    const Property& indices = face_->properties[static_cast<std::size_t>(face_indices_)];
    if (!indices.is_list) Fail("face property '{}' must be a list", indices.name);
    if (!IsInteger(indices.type)) {
      Fail("face property '{}' must have an integer item type, not '{}'", indices.name, NameOf(indices.type));
    }
    line_ = 0;
  }

  // Refuses counts the file cannot possibly hold, before anything is sized from them. Every item
  // of an element with properties takes at least one byte per binary scalar or list count, or one
  // ascii value of at least one character plus a separator (so N values need 2N-1 characters).
  // Every loop over a body then also consumes input, so none can run longer than the file allows.
  void CheckCountsAgainstSize() {
    const std::uint64_t body = data_.size() - body_offset_;
    const bool ascii = format_ == Format::kAscii;
    const std::uint64_t budget = ascii ? (body + 1) / 2 : body;
    std::uint64_t used = 0;
    for (const Element& e : elements_) {
      std::uint64_t per_item = 0;
      for (const Property& p : e.properties) {
        per_item += ascii ? 1 : SizeOf(p.is_list ? p.count_type : p.type);
        // A face's index list needs at least 3 items, so they count too; this also bounds what
        // ReadFaces reserves to a small multiple of the file size.
        if (&e == face_ && &p == &face_->properties[static_cast<std::size_t>(face_indices_)]) {
          per_item += ascii ? 3 : 3 * SizeOf(p.type);
        }
      }
      if (per_item == 0) continue;  // no properties: nothing is read, whatever the count
      if (e.count > (budget - used) / per_item) {
        line_ = e.line;
        Fail("element '{}' count {} is too large for the {} bytes of data in the file", Printable(e.name),
             e.count, body);
      }
      used += e.count * per_item;
    }
  }

  // ---- Body ----

  template <Format F>
  void ParseBody() {
    pos_ = body_offset_;
    // Ascii body lines continue the header's numbering; binary errors name the element item only.
    line_ = F == Format::kAscii ? header_lines_ + 1 : 0;
    for (const Element& e : elements_) {
      if (e.properties.empty()) continue;
      element_ = &e;
      if (&e == vertex_) {
        ReadVertices<F>(e);
      } else if (&e == face_) {
        ReadFaces<F>(e);
      } else {
        for (index_ = 0; index_ < e.count; ++index_) {
          BeginItem<F>();
          for (const Property& p : e.properties) SkipProperty<F>(p);
          EndItem<F>();
        }
      }
    }
    element_ = nullptr;
    // Binary files may carry padding after the data, but leftover ascii values mean the counts
    // in the header do not describe the body.
    if constexpr (F == Format::kAscii) {
      SkipBlankLines();
      if (pos_ < data_.size()) Fail("unexpected data after the last element");
    }
  }

  template <Format F>
  void ReadVertices(const Element& e) {
    // Sizing from the count is safe: CheckCountsAgainstSize bounded it by the file size.
    positions_.resize(e.count);
    if (has_normals_) normals_.resize(e.count);
    for (index_ = 0; index_ < e.count; ++index_) {
      BeginItem<F>();
      double v[6] = {};
      for (std::size_t i = 0; i < e.properties.size(); ++i) {
        const Property& p = e.properties[i];
        if (vertex_roles_[i] == kNone) {
          SkipProperty<F>(p);
        } else {
          v[vertex_roles_[i]] = Read<F>(p.type);
        }
      }
      EndItem<F>();
      positions_[index_] = glm::vec3(ToFloat(v[kX], "coordinate"), ToFloat(v[kY], "coordinate"),
                                     ToFloat(v[kZ], "coordinate"));
      if (has_normals_) {
        normals_[index_] =
            glm::vec3(ToFloat(v[kNx], "normal"), ToFloat(v[kNy], "normal"), ToFloat(v[kNz], "normal"));
      }
    }
  }

  float ToFloat(double v, const char* what) const {
    if (!std::isfinite(v)) Fail("non-finite {}", what);
    // Checked explicitly: converting an out-of-range double to float is undefined behaviour.
    if (std::fabs(v) > std::numeric_limits<float>::max()) Fail("{} {} does not fit in a float", what, v);
    return static_cast<float>(v);
  }

  template <Format F>
  void ReadFaces(const Element& e) {
    triangles_.reserve(e.count * 3);  // bounded by CheckCountsAgainstSize; a lower bound for fans
    const Property& list = e.properties[static_cast<std::size_t>(face_indices_)];
    for (index_ = 0; index_ < e.count; ++index_) {
      BeginItem<F>();
      for (std::size_t i = 0; i < e.properties.size(); ++i) {
        const Property& p = e.properties[i];
        if (&p != &list) {
          SkipProperty<F>(p);
          continue;
        }
        const std::uint64_t n = ReadCount<F>(p);
        if (n < 3) Fail("{} vertex indices, a face needs at least 3", n);
        // Stop a bogus binary count here rather than after emitting triangles for the rest of the file.
        if constexpr (F != Format::kAscii) RequireBytes(n * SizeOf(p.type));
        // Fan triangulation (v0, vi, vi+1): exact for the convex polygons scanners write.
        const std::uint32_t v0 = ReadIndex<F>(p.type);
        std::uint32_t prev = ReadIndex<F>(p.type);
        for (std::uint64_t k = 2; k < n; ++k) {
          const std::uint32_t cur = ReadIndex<F>(p.type);
          triangles_.insert(triangles_.end(), {v0, prev, cur});
          prev = cur;
        }
      }
      EndItem<F>();
    }
  }

  template <Format F>
  std::uint32_t ReadIndex(Type type) {
    // Integer types only (checked in ResolveElements), so the double holds the value exactly.
    const double v = Read<F>(type);
    const auto index = static_cast<std::int64_t>(v);
    if (index < 0) Fail("negative vertex index {}", index);
    // Checked against the declared count: the face element may come before the vertices.
    if (static_cast<std::uint64_t>(index) >= vertex_->count) {
      if (vertex_->count == 0) Fail("vertex index {} out of range (no vertices)", index);
      Fail("vertex index {} out of range (0..{})", index, vertex_->count - 1);
    }
    return static_cast<std::uint32_t>(index);
  }

  template <Format F>
  std::uint64_t ReadCount(const Property& p) {
    const double n = Read<F>(p.count_type);  // an integer type, so exact
    if (n < 0) Fail("negative list length {} for '{}'", static_cast<std::int64_t>(n), Printable(p.name));
    return static_cast<std::uint64_t>(n);
  }

  template <Format F>
  void SkipProperty(const Property& p) {
    if (!p.is_list) {
      Read<F>(p.type);
      return;
    }
    const std::uint64_t n = ReadCount<F>(p);
    if constexpr (F == Format::kAscii) {
      // Parsed, not just stepped over, so malformed values are reported wherever they are.
      for (std::uint64_t k = 0; k < n; ++k) Read<F>(p.type);
    } else {
      RequireBytes(n * SizeOf(p.type));  // n < 2^32 and sizes <= 8: no overflow
      pos_ += static_cast<std::size_t>(n * SizeOf(p.type));
    }
  }

  void RequireBytes(std::uint64_t n) const {
    if (n > data_.size() - pos_) Fail("unexpected end of file");
  }

  template <Format F>
  double Read(Type type) {
    if constexpr (F == Format::kAscii) {
      return ReadAscii(type);
    } else {
      return ReadBinary<F>(type);
    }
  }

  // -- Binary --

  template <Format F>
  double ReadBinary(Type type) {
    RequireBytes(SizeOf(type));
    const char* p = data_.data() + pos_;
    pos_ += SizeOf(type);
    switch (type) {
      case Type::kInt8: return static_cast<std::int8_t>(Load<std::uint8_t, F>(p));
      case Type::kUInt8: return Load<std::uint8_t, F>(p);
      case Type::kInt16: return static_cast<std::int16_t>(Load<std::uint16_t, F>(p));
      case Type::kUInt16: return Load<std::uint16_t, F>(p);
      case Type::kInt32: return static_cast<std::int32_t>(Load<std::uint32_t, F>(p));
      case Type::kUInt32: return Load<std::uint32_t, F>(p);
      case Type::kFloat32: return std::bit_cast<float>(Load<std::uint32_t, F>(p));
      case Type::kFloat64: return std::bit_cast<double>(Load<std::uint64_t, F>(p));
    }
    return 0;  // not reached: every enumerator is handled above
  }

  template <typename U, Format F>
  static U Load(const char* p) {
    U v;
    std::memcpy(&v, p, sizeof v);  // the data has no alignment guarantee
    constexpr bool kFileBig = F == Format::kBinaryBig;
    if constexpr (kFileBig != (std::endian::native == std::endian::big)) v = ByteSwap(v);
    return v;
  }

  // -- Ascii --
  // Each element item is one line, as the format specifies; holding to that turns a wrong count
  // into an error on the line where it happens instead of a misparse of everything after it.

  template <Format F>
  void BeginItem() {
    if constexpr (F == Format::kAscii) {
      SkipBlankLines();
      if (pos_ >= data_.size()) Fail("unexpected end of file");
    }
  }

  template <Format F>
  void EndItem() {
    if constexpr (F == Format::kAscii) {
      while (pos_ < data_.size() && IsSpace(data_[pos_])) ++pos_;
      if (pos_ < data_.size() && data_[pos_] != '\n') Fail("more values on the line than the header declares");
    }
  }

  // Moves to the next non-blank character, counting the lines passed.
  void SkipBlankLines() {
    for (; pos_ < data_.size(); ++pos_) {
      if (data_[pos_] == '\n') {
        ++line_;
      } else if (!IsSpace(data_[pos_])) {
        break;
      }
    }
  }

  std::string_view NextToken() {
    while (pos_ < data_.size() && IsSpace(data_[pos_])) ++pos_;
    if (pos_ >= data_.size()) Fail("unexpected end of file");
    if (data_[pos_] == '\n') Fail("fewer values on the line than the header declares");
    const std::size_t start = pos_;
    while (pos_ < data_.size() && data_[pos_] != '\n' && !IsSpace(data_[pos_])) ++pos_;
    return data_.substr(start, pos_ - start);
  }

  double ReadAscii(Type type) {
    const std::string_view token = NextToken();
    std::string_view digits = token;
    // from_chars rejects a leading '+', which some writers emit.
    if (digits.size() > 1 && digits[0] == '+' && digits[1] != '+' && digits[1] != '-') digits.remove_prefix(1);
    const char* first = digits.data();
    const char* last = first + digits.size();

    if (IsInteger(type)) {
      std::int64_t v = 0;
      const auto r = std::from_chars(first, last, v);
      if (r.ptr != last || (r.ec != std::errc() && r.ec != std::errc::result_out_of_range)) {
        Fail("'{}' is not a valid {}", Printable(token), NameOf(type));
      }
      const auto [lo, hi] = RangeOf(type);
      if (r.ec != std::errc() || v < lo || v > hi) Fail("value {} out of range for {}", Printable(token), NameOf(type));
      return static_cast<double>(v);
    }

    if (type == Type::kFloat32) {
      float v = 0;
      const auto r = std::from_chars(first, last, v);
      if (r.ptr == last && r.ec == std::errc()) return v;
      if (r.ptr == last && r.ec == std::errc::result_out_of_range) return OutOfRangeValue(digits, type);
    } else {
      double v = 0;
      const auto r = std::from_chars(first, last, v);
      if (r.ptr == last && r.ec == std::errc()) return v;
      if (r.ptr == last && r.ec == std::errc::result_out_of_range) return OutOfRangeValue(digits, type);
    }
    Fail("'{}' is not a valid {}", Printable(token), NameOf(type));
  }

  // from_chars leaves the value unset when it over- or underflows, but the difference matters: an
  // underflow is a legitimate zero, an overflow an infinity that the coordinate check rejects.
  // strtof/strtod report both as values; the token is already known to be a valid number.
  static double OutOfRangeValue(std::string_view digits, Type type) {
    const std::string copy(digits);
    return type == Type::kFloat32 ? std::strtof(copy.c_str(), nullptr) : std::strtod(copy.c_str(), nullptr);
  }

  // ---- Result ----

  MeshData BuildMesh() {
    SubMesh mesh;
    mesh.name = StemWithoutGz(path_);
    mesh.positions.reserve(triangles_.size());
    for (std::uint32_t i : triangles_) mesh.positions.push_back(positions_[i]);
    if (has_normals_) {
      mesh.normals.reserve(triangles_.size());
      for (std::uint32_t i : triangles_) mesh.normals.push_back(normals_[i]);
    }
    mesh.material.assign(triangles_.size() / 3, -1);
    MeshData data;
    data.submeshes.push_back(std::move(mesh));
    return data;
  }

  const std::filesystem::path& path_;
  const std::string file_;
  const std::string_view data_;

  // Header.
  Format format_ = Format::kAscii;
  std::vector<Element> elements_;
  std::size_t body_offset_ = 0;
  int header_lines_ = 0;
  const Element* vertex_ = nullptr;
  const Element* face_ = nullptr;
  std::vector<int> vertex_roles_;  // Role per vertex property
  bool has_normals_ = false;
  int face_indices_ = -1;  // which face property holds the vertex indices

  // Body.
  std::size_t pos_ = 0;
  std::vector<glm::vec3> positions_;
  std::vector<glm::vec3> normals_;
  std::vector<std::uint32_t> triangles_;  // 3 vertex indices per triangle

  // Where we are, for error messages: 0 when no line applies (binary body, header-wide checks).
  int line_ = 0;
  const Element* element_ = nullptr;
  std::uint64_t index_ = 0;
};

}  // namespace

MeshData LoadPly(const std::filesystem::path& path) {
  const std::string data = ReadInputFile(path, {"mesh", kMaxDataFileBytes, Gzip::kByExtension});
  return PlyParser(path, data).Parse();
}

}  // namespace rayspace
