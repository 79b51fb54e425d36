// The call codec (verify/call_codec.h) on every call of emu/calls.h: a call filled with distinct values
// survives encode -> decode -> encode byte for byte, every field reaches the buffer set, and a set
// missing a buffer or scalar is refused naming it. Also: CheckInputs refuses out-of-range inputs.
#include <doctest/doctest.h>

#include <algorithm>
#include <bit>
#include <cstring>
#include <deque>
#include <memory>
#include <set>
#include <span>
#include <string>
#include <tuple>
#include <type_traits>
#include <utility>
#include <variant>

#include "rayspace/emu/calls.h"
#include "rayspace/error.h"
#include "rayspace/verify/call_codec.h"
#include "test_util.h"

using namespace rayspace;
using namespace rayspace::emu;
using verify::BufferSet;
namespace cd = verify::codec_detail;

namespace {

// Fills every field of a call with values that differ from each other and from the defaults:
// arrays of a few elements with distinct bytes, scalars counting up from 101, floats with odd bits.
class Filler {
 public:
  Filler() {
    // A small scene the codec's GetScene accepts (triangle ids name existing materials and objects).
    scene_.triangles.resize(2);
    scene_.normals.resize(2);
    scene_.materials.resize(2);
    scene_.lights.resize(1);
    Bytes(scene_.triangles);
    Bytes(scene_.normals);
    Bytes(scene_.materials);
    Bytes(scene_.lights);
    scene_.info = {{glm::uvec4(1, 0, 7, 8)}, {glm::uvec4(0, 1, 9, 10)}};
    scene_.objects = {glm::uvec4(0, 1, 11, 12), glm::uvec4(1, 1, 13, 14)};
    scene_.lo = glm::vec3(-1.5f, -2.5f, -3.5f);
    scene_.hi = glm::vec3(4.5f, 5.5f, 6.5f);
  }

  template <typename S>
  void Fill(S& s) {
    ForEachField(s, [&](std::string_view, auto& f) { FillField(f); });
  }

 private:
  template <typename T>
  void Bytes(std::vector<T>& v) {
    std::vector<std::uint8_t> pattern;
    for (std::size_t i = 0; i < v.size() * sizeof(T); ++i) pattern.push_back(static_cast<std::uint8_t>(seed_ * 31 + i * 7 + 1));
    if (!pattern.empty()) std::memcpy(static_cast<void*>(v.data()), pattern.data(), pattern.size());
    ++seed_;
  }
  template <typename T>
  std::vector<T>& Array() {
    auto v = std::make_shared<std::vector<T>>(2 + seed_ % 3);
    Bytes(*v);
    keep_.push_back(v);
    return *v;
  }

  template <typename F>
  void FillField(F& f) {
    if constexpr (cd::IsSpan<F>::value) {
      f = Array<typename cd::IsSpan<F>::Elem>();
    } else if constexpr (cd::IsVectorPtr<F>::value) {
      f = &Array<typename cd::IsVectorPtr<F>::Elem>();
    } else if constexpr (std::is_same_v<F, const SceneBuffers*>) {
      f = &scene_;
    } else if constexpr (std::is_same_v<F, layout::FrameConstants>) {
      std::vector<layout::FrameConstants> one(1);
      Bytes(one);
      f = one[0];
    } else if constexpr (std::is_same_v<F, float>) {
      f = std::bit_cast<float>(0x3F800001u + (scalar_++ << 16));  // odd bit patterns: every bit counts
    } else if constexpr (std::is_enum_v<F>) {
      f = static_cast<F>(static_cast<std::underlying_type_t<F>>(f) + 1);  // the next value after the default
    } else if constexpr (std::is_integral_v<F>) {
      f = static_cast<F>(scalar_++);
    } else {
      static_assert(HasFields<F>, "a call field the filler does not know");
      Fill(f);
    }
  }

  SceneBuffers scene_;
  std::deque<std::shared_ptr<void>> keep_;
  std::uint32_t seed_ = 1, scalar_ = 101;
};

// Where each field of a call lands in its buffer set: buffer names, scalar names, and the buffers of
// in-place arrays (which a set may leave out).
struct Layout {
  std::set<std::string> blobs, scalars, optional;
};

template <typename S>
void Collect(const S& s, Layout& l) {
  ForEachField(s, [&](std::string_view name_view, const auto& f) {
    using F = std::decay_t<decltype(f)>;
    const std::string name(name_view);
    if constexpr (cd::IsSpan<F>::value || std::is_same_v<F, layout::FrameConstants> || std::is_same_v<F, std::uint64_t>) {
      l.blobs.insert(name);
    } else if constexpr (cd::IsVectorPtr<F>::value) {
      l.blobs.insert(name);
      l.optional.insert(name);
    } else if constexpr (std::is_same_v<F, const SceneBuffers*>) {
      for (const char* b : {"scene.triangles", "scene.normals", "scene.info", "scene.materials", "scene.lights",
                            "scene.objects", "scene.box"})
        l.blobs.insert(b);
    } else if constexpr (std::is_same_v<F, float>) {
      l.scalars.insert(name + "_bits");
    } else if constexpr (std::is_integral_v<F> || std::is_enum_v<F>) {
      l.scalars.insert(name);
    } else {
      Collect(f, l);
    }
  });
}

template <typename T>
bool SameBytes(std::span<const T> a, std::span<const T> b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size_bytes()) == 0);
}
template <typename T>
bool SameBytes(const std::vector<T>& a, const std::vector<T>& b) {
  return SameBytes(std::span<const T>(a), std::span<const T>(b));
}

template <typename F>
void CheckSameField(std::string_view name, const F& a, const F& b);

// Field by field: the decoded call holds the values the original did (bits for floats).
template <typename S>
void CheckSameFields(const S& a, const S& b) {
  auto fa = a.Tie();
  auto fb = b.Tie();
  [&]<std::size_t... I>(std::index_sequence<I...>) {
    (CheckSameField(FieldName(S::kFieldNames, I), std::get<I>(fa), std::get<I>(fb)), ...);
  }(std::make_index_sequence<std::tuple_size_v<decltype(fa)>>{});
}

template <typename F>
void CheckSameField(std::string_view name, const F& a, const F& b) {
  INFO("field " << std::string(name));
  if constexpr (cd::IsSpan<F>::value) {
    CHECK(SameBytes(a, b));
  } else if constexpr (cd::IsVectorPtr<F>::value) {
    REQUIRE(a != nullptr);
    REQUIRE(b != nullptr);
    CHECK(SameBytes(*a, *b));
  } else if constexpr (std::is_same_v<F, const SceneBuffers*>) {
    REQUIRE(b != nullptr);
    CHECK(SameBytes(a->triangles, b->triangles));
    CHECK(SameBytes(a->normals, b->normals));
    CHECK(SameBytes(a->info, b->info));
    CHECK(SameBytes(a->materials, b->materials));
    CHECK(SameBytes(a->lights, b->lights));
    CHECK(SameBytes(a->objects, b->objects));
    CHECK(a->lo == b->lo);
    CHECK(a->hi == b->hi);
  } else if constexpr (std::is_same_v<F, layout::FrameConstants>) {
    CHECK(std::memcmp(&a, &b, sizeof(F)) == 0);
  } else if constexpr (std::is_same_v<F, float>) {
    CHECK(std::bit_cast<std::uint32_t>(a) == std::bit_cast<std::uint32_t>(b));
  } else if constexpr (std::is_integral_v<F> || std::is_enum_v<F>) {
    CHECK(a == b);
  } else {
    CheckSameFields(a, b);
  }
}

template <typename T>
void CopyAs(BufferSet& out, const std::string& name, const verify::Blob& b) {
  std::vector<T> v(b.bytes().size() / sizeof(T));
  if (!v.empty()) std::memcpy(v.data(), b.bytes().data(), b.bytes().size());
  out.Put(name, v);
}

// `in` without buffer `drop` (blobs are typed: each is copied back as its element type).
BufferSet Without(const BufferSet& in, const std::string& drop) {
  using verify::ElemType;
  BufferSet out;
  out.scalars = in.scalars;
  for (const auto& [name, b] : in.blobs()) {
    if (name == drop) continue;
    switch (b.type) {
      case ElemType::kU8: CopyAs<std::uint8_t>(out, name, b); break;
      case ElemType::kU32: CopyAs<std::uint32_t>(out, name, b); break;
      case ElemType::kU64: CopyAs<std::uint64_t>(out, name, b); break;
      case ElemType::kF32: CopyAs<float>(out, name, b); break;
      case ElemType::kVec4: CopyAs<glm::vec4>(out, name, b); break;
      case ElemType::kUvec4: CopyAs<glm::uvec4>(out, name, b); break;
      case ElemType::kRay: CopyAs<layout::Ray>(out, name, b); break;
      case ElemType::kSurface: CopyAs<layout::Surface>(out, name, b); break;
      case ElemType::kNode: CopyAs<layout::ConeNode>(out, name, b); break;
      case ElemType::kTriangle: CopyAs<layout::Triangle>(out, name, b); break;
      case ElemType::kNormals: CopyAs<layout::TriangleNormals>(out, name, b); break;
      case ElemType::kInfo: CopyAs<layout::TriangleInfo>(out, name, b); break;
      case ElemType::kMaterial: CopyAs<layout::Material>(out, name, b); break;
      case ElemType::kLight: CopyAs<layout::Light>(out, name, b); break;
      case ElemType::kFrame: CopyAs<layout::FrameConstants>(out, name, b); break;
    }
  }
  return out;
}

void CheckSameSet(const BufferSet& a, const BufferSet& b) {
  CHECK(a.scalars == b.scalars);
  REQUIRE(a.blobs().size() == b.blobs().size());
  for (const auto& [name, blob] : a.blobs()) {
    INFO("buffer " << name);
    REQUIRE(b.Has(name));
    const verify::Blob& other = b.blobs().at(name);
    CHECK(blob.type == other.type);
    CHECK(std::ranges::equal(blob.bytes(), other.bytes()));
  }
}

// The InputError message of f(), or "" when it does not throw one.
template <typename F>
std::string InputErrorOf(F&& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

template <typename C>
void RoundTrip() {
  const std::string call(C::kName);
  INFO("call " << call);
  Filler filler;
  C c;
  filler.Fill(c);
  const BufferSet first = verify::EncodeCall(c);
  const auto decoded = verify::DecodeCall<C>(first);
  const BufferSet second = verify::EncodeCall(decoded.call);
  CheckSameSet(first, second);
  CheckSameFields(c, decoded.call);

  // Every field is in the set, and nothing else is.
  Layout l;
  Collect(c, l);
  std::set<std::string> blobs, scalars;
  for (const auto& [name, b] : first.blobs()) {
    blobs.insert(name);
    CHECK(!b.bytes().empty());
  }
  for (const auto& [name, v] : first.scalars.items()) scalars.insert(name);
  CHECK(blobs == l.blobs);
  CHECK(scalars == l.scalars);

  // A missing buffer is refused naming it; a missing in-place array decodes as none.
  for (const std::string& name : l.blobs) {
    INFO("without buffer " << name);
    const BufferSet partial = Without(first, name);
    if (l.optional.count(name)) {
      const auto d = verify::DecodeCall<C>(partial);
      ForEachField(d.call, [&](std::string_view field, const auto& f) {
        if constexpr (cd::IsVectorPtr<std::decay_t<decltype(f)>>::value)
          if (field == name) CHECK(f == nullptr);
      });
    } else {
      const std::string msg = InputErrorOf([&] { verify::DecodeCall<C>(partial); });
      CHECK(msg.find("'" + name + "'") != std::string::npos);
    }
  }
  for (const std::string& name : l.scalars) {
    INFO("without scalar " << name);
    BufferSet partial = first;
    partial.scalars.erase(name);
    const std::string msg = InputErrorOf([&] { verify::DecodeCall<C>(partial); });
    CHECK(msg.find("'" + name + "'") != std::string::npos);
  }
}

}  // namespace

TEST_CASE("call codec: every call survives encode, decode, encode byte for byte, and missing inputs are named") {
  std::set<std::string_view> names;
#define RS_ROUND_TRIP(C)                  \
  RoundTrip<call::C>();                   \
  CHECK(names.insert(call::C::kName).second);
  RS_FRAME_CALLS(RS_ROUND_TRIP)
  RS_HIERARCHY_CALLS(RS_ROUND_TRIP)
#undef RS_ROUND_TRIP
  CHECK(names.size() >= 18);
}

TEST_CASE("call codec: float scalars keep their bits, NaN payloads included") {
  call::ObjectMask c;
  c.eps = std::bit_cast<float>(0x7FC01234u);
  const auto d = verify::DecodeCall<call::ObjectMask>(verify::EncodeCall(c));
  CHECK(std::bit_cast<std::uint32_t>(d.call.eps) == 0x7FC01234u);
}

TEST_CASE("call codec: a Compacted result is its pairs and a one-element tested buffer, both compared by name") {
  const call::TraverseTopCompacted c;
  const Compacted r{.pairs = {3, 1, 4}, .tested = (std::uint64_t{1} << 40) + 5};  // beyond 2^32 and a JSON double's care
  const BufferSet out = verify::EncodeOutputs(c, &r);
  REQUIRE(out.Has("pairs"));
  REQUIRE(out.Has("tested"));
  CHECK(out.blobs().size() == 2);
  CHECK(out.blobs().at("tested").type == verify::ElemType::kU64);
  const Compacted back = verify::DecodeOutputs(out, c);
  CHECK(back.pairs == r.pairs);
  CHECK(back.tested == r.tested);
  Compacted other = r;
  other.tested -= 1;
  const BufferSet out2 = verify::EncodeOutputs(c, &other);
  const BufferComparison t = verify::CompareBlobs("traverse.compact", "tested", out.blobs().at("tested"), out2.blobs().at("tested"), "vulkan");
  CHECK_FALSE(t.Equal());
  CHECK(t.Summary().find("traverse.compact/tested: 1 of 1 elements differ; first at 0") == 0);
  CHECK(verify::CompareBlobs("traverse.compact", "pairs", out.blobs().at("pairs"), out2.blobs().at("pairs"), "vulkan").Equal());
}

// ---- output ranges ----------------------------------------------------------------------------------

namespace {

// A result with a few distinct bytes in every array and count.
template <typename S>
void FillResult(S& s, std::uint8_t& seed) {
  auto fill = [&](auto& v) {
    using V = std::decay_t<decltype(v)>;
    if constexpr (cd::IsVector<V>::value || cd::IsUninitVector<V>::value) {
      v.resize(2 + seed % 3);
      auto* p = reinterpret_cast<std::uint8_t*>(v.data());
      for (std::size_t i = 0; i < v.size() * sizeof(typename V::value_type); ++i) p[i] = static_cast<std::uint8_t>(seed * 17 + i);
      ++seed;
    } else if constexpr (std::is_same_v<V, std::uint64_t>) {
      v = (std::uint64_t{seed++} << 40) + 7;
    } else if constexpr (HasFields<V>) {
      FillResult(v, seed);
    }
  };
  if constexpr (HasFields<S>) ForEachField(s, [&](std::string_view, auto& f) { fill(f); });
  else fill(s);
}

// Every output range names a buffer EncodeOutputs writes, holds its bytes at its place in memory and
// its element size, and every buffer has a range.
template <typename C>
void CheckOutputRanges() {
  INFO("call " << C::kName);
  Filler filler;
  C c;
  filler.Fill(c);
  using R = std::conditional_t<std::is_void_v<typename C::Result>, std::monostate, typename C::Result>;
  R r{};
  std::uint8_t seed = 3;
  FillResult(r, seed);
  BufferSet out;
  if constexpr (std::is_void_v<typename C::Result>) out = verify::EncodeOutputs(c, nullptr);
  else out = verify::EncodeOutputs(c, &r);
  std::set<std::string> ranges, blobs;
  verify::ForEachOutputRange(c, &r, [&](std::string_view name_view, const void* first, std::size_t bytes, std::size_t elem) {
    const std::string name(name_view);
    INFO("output " << name);
    ranges.insert(name);
    REQUIRE(out.Has(name));
    const verify::Blob& b = out.blobs().at(name);
    CHECK(b.bytes().size() == bytes);
    CHECK((bytes == 0 || std::memcmp(b.bytes().data(), first, bytes) == 0));
    CHECK(verify::Info(b.type).bytes == elem);
  });
  for (const auto& [name, blob] : out.blobs()) blobs.insert(name);
  CHECK(ranges == blobs);

  // The diff's copy-free path gives the same set, and decoding the set given up gives what decoding
  // a kept one does.
  BufferSet moved;
  if constexpr (std::is_void_v<typename C::Result>) moved = verify::MoveOutputs(c, nullptr);
  else moved = verify::MoveOutputs(c, &r);
  CheckSameSet(out, moved);
  if constexpr (!std::is_void_v<typename C::Result>) {
    const R kept = verify::DecodeOutputs(out, c);
    const BufferSet from_kept = verify::EncodeOutputs(c, &kept);
    R taken = verify::DecodeOutputs(std::move(moved), c);
    CheckSameSet(from_kept, verify::EncodeOutputs(c, &taken));
    CheckSameSet(out, from_kept);
  }
}

}  // namespace

TEST_CASE("call codec: every call's output ranges are its encoded outputs, in place in memory") {
  std::set<std::string_view> names;
#define RS_RANGES(C)             \
  CheckOutputRanges<call::C>();  \
  CHECK(names.insert(call::C::kName).second);
  RS_FRAME_CALLS(RS_RANGES)
  RS_HIERARCHY_CALLS(RS_RANGES)
#undef RS_RANGES
  CHECK(names.size() >= 18);  // every call of the registry, none twice
}

TEST_CASE("buffer set: adopted arrays move out without a copy, viewed ones stay the caller's, a held view forces a copy") {
  std::vector<std::uint32_t> v = {1, 2, 3, 4};
  const std::uint32_t* first = v.data();
  BufferSet s;
  s.Put("a", std::move(v));
  CHECK(s.View<std::uint32_t>("a").data() == first);
  std::vector<std::uint32_t> back = s.Take<std::uint32_t>("a");
  CHECK(back.data() == first);  // moved, not copied
  CHECK(back == std::vector<std::uint32_t>{1, 2, 3, 4});
  CHECK(s.View<std::uint32_t>("a").empty());

  s.Put("b", std::vector<std::uint32_t>{5, 6});
  const std::shared_ptr<const void> held = s.Owner("b");  // a decoded call still views it
  const std::vector<std::uint32_t> copy = s.Take<std::uint32_t>("b");
  CHECK(copy.data() != s.View<std::uint32_t>("b").data());
  CHECK(s.Get<std::uint32_t>("b") == copy);

  const std::vector<float> caller = {0.5f, -1.0f};
  s.PutView("c", std::span<const float>(caller));
  CHECK(s.View<float>("c").data() == caller.data());
  CHECK(s.Owner("c") == nullptr);
  CHECK(s.Take<float>("c").data() != caller.data());  // never moved out of the caller's array

  const std::string wrong = InputErrorOf([&] { s.View<std::uint8_t>("c"); });
  CHECK(wrong.find("buffer 'c' holds f32, expected u8") != std::string::npos);
}

TEST_CASE("call codec: a viewed call decodes to views of the caller's arrays, a copied one to its own copies") {
  call::Reduce c;
  const std::vector<std::uint8_t> flags = {1, 0, 1};
  const std::vector<std::uint32_t> values = {7, 8, 9};
  c.flags = flags;
  c.values = values;
  const BufferSet viewed = verify::ViewCall(c), copied = verify::EncodeCall(c);
  CheckSameSet(viewed, copied);
  const auto dv = verify::DecodeCall<call::Reduce>(viewed);
  const auto dc = verify::DecodeCall<call::Reduce>(copied);
  CHECK(dv.call.values.data() == values.data());
  CHECK(dc.call.values.data() != values.data());
  CHECK(std::ranges::equal(dc.call.values, values));
  CHECK(std::ranges::equal(dc.call.flags, flags));
}

// ---- CheckInputs ----------------------------------------------------------------------------------

namespace {

// CheckInputs(c) throws an InputError naming the call and `input`.
template <typename C>
void Refused(const C& c, const std::string& input) {
  const std::string msg = InputErrorOf([&] { CheckInputs(c); });
  INFO("call " << C::kName << ", input " << input << ": '" << msg << "'");
  CHECK(msg.rfind(std::string(C::kName) + ":", 0) == 0);
  CHECK(msg.find(input) != std::string::npos);
}

template <typename C>
void Accepted(const C& c) {
  INFO("call " << C::kName);
  CHECK(InputErrorOf([&] { CheckInputs(c); }) == "");
}

SceneBuffers FourTriangles() {
  Scene s;
  s.materials.push_back(test::Diffuse("m", glm::vec3(0.5f)));
  test::AddQuad(s, "a", {-1, -1, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0});
  test::AddQuad(s, "b", {-1, -1, 1}, {1, -1, 1}, {1, 1, 1}, {-1, 1, 1});
  return FlattenScene(s);
}

std::uint32_t Pair(std::uint32_t node, std::uint32_t tri) { return node << layout::kPairTriangleBits | tri; }

// A pair naming a node or a triangle one past the fixture's end is refused.
template <typename C>
void RefusesFarPairs(const C& ok) {
  const std::vector<std::uint32_t> far_node = {Pair(2, 0)}, far_tri = {Pair(0, 4)};
  C c = ok;
  c.pairs = far_node;
  Refused(c, "'pairs' element 0");
  c.pairs = far_tri;
  Refused(c, "'pairs' element 0");
}

}  // namespace

TEST_CASE("CheckInputs: out-of-range inputs are refused naming the call and the input") {
  const SceneBuffers scene = FourTriangles();
  const std::vector<layout::ConeNode> nodes(2);
  const std::vector<glm::vec4> spheres(4), three_spheres(3);
  const std::vector<layout::Ray> rays(3);

  SUBCASE("traverse.top") {
    const call::TraverseTop ok{.top = nodes, .t0 = 0, .t1 = 2, .b0 = 0, .b1 = 4, .tri_spheres = spheres, .scene = &scene,
                               .object_mask = {}, .eps = 0.0f};
    Accepted(ok);
    call::TraverseTop c = ok;
    c.t1 = 3;
    Refused(c, "top nodes [0, 3)");
    c = ok;
    c.b1 = 5;
    Refused(c, "triangles [0, 5)");
    c = ok;
    c.tri_spheres = three_spheres;
    Refused(c, "'tri_spheres'");
    const std::vector<std::uint8_t> mask(3, 1);
    c = ok;
    c.object_mask = mask;
    Refused(c, "'object_mask'");
  }
  SUBCASE("traverse.level") {
    const std::vector<std::uint32_t> first = {0, 1, 2}, pairs = {Pair(0, 3), Pair(1, 0)};
    const call::TraverseLevel ok{.pairs = pairs, .nodes = nodes, .first = first, .base_up = 0, .base = 0, .children_max = 1,
                                 .b0 = 0, .tri_spheres = spheres, .eps = 0.0f};
    Accepted(ok);
    RefusesFarPairs(ok);
    call::TraverseLevel c = ok;
    const std::vector<std::uint32_t> bad_first = {0, 2, 1};
    c.first = bad_first;
    Refused(c, "'first'");
    c = ok;
    c.children_max = 256;
    Refused(c, "'children_max'");
  }
  SUBCASE("traverse.compact.top and traverse.compact.level: the inputs of traverse.top and traverse.level") {
    call::TraverseTopCompacted top;
    static_cast<call::TraverseTop&>(top) = {.top = nodes, .t0 = 0, .t1 = 2, .b0 = 0, .b1 = 4, .tri_spheres = spheres, .scene = &scene,
                                            .object_mask = {}, .eps = 0.0f};
    Accepted(top);
    top.t1 = 3;
    Refused(top, "top nodes [0, 3)");
    const std::vector<std::uint32_t> first = {0, 1, 2}, pairs = {Pair(0, 3), Pair(1, 0)};
    call::TraverseLevelCompacted level;
    static_cast<call::TraverseLevel&>(level) = {.pairs = pairs, .nodes = nodes, .first = first, .base_up = 0, .base = 0,
                                                .children_max = 1, .b0 = 0, .tri_spheres = spheres, .eps = 0.0f};
    Accepted(level);
    RefusesFarPairs(level);
    level.children_max = 256;
    Refused(level, "'children_max'");
  }
  SUBCASE("intersect") {
    const std::vector<std::uint32_t> order = {2, 0, 1}, first1 = {0, 2, 3}, pairs = {Pair(1, 3)};
    std::vector<std::uint64_t> hits(3), short_hits(2);
    const call::Intersect ok{.pairs = pairs, .first1 = first1, .base1 = 0, .b0 = 0, .order = order, .rays = rays,
                             .scene = &scene, .hits = &hits, .occluded = nullptr};
    Accepted(ok);
    RefusesFarPairs(ok);
    call::Intersect c = ok;
    const std::vector<std::uint32_t> bad_order = {2, 3, 1};
    c.order = bad_order;
    Refused(c, "'order' element 1");
    c = ok;
    c.hits = &short_hits;
    Refused(c, "'hits'");
    c = ok;
    c.hits = nullptr;
    Refused(c, "'hits' and 'occluded'");
  }
  SUBCASE("decompress") {
    const std::vector<std::uint32_t> key = {5, 3}, base = {0, 2}, size = {2, 1}, order = {1, 0}, bad_order = {1, 2};
    const call::Decompress ok{.chunk_key = key, .chunk_base = base, .chunk_size = size, .chunk_order = order};
    Accepted(ok);
    call::Decompress c = ok;
    c.chunk_order = bad_order;
    Refused(c, "'chunk_order' element 1");
    c = ok;
    c.chunk_size = In<std::uint32_t>(size).first(1);
    Refused(c, "'chunk_size'");
  }
  SUBCASE("build.leaves") {
    const std::vector<std::uint32_t> order = {2, 0, 1}, first = {0, 2, 3}, bad_order = {2, 0, 3}, bad_first = {0, 2, 4};
    const call::BuildLeaves ok{.rays = rays, .order = order, .first = first};
    Accepted(ok);
    call::BuildLeaves c = ok;
    c.order = bad_order;
    Refused(c, "'order' element 2");
    c = ok;
    c.first = bad_first;
    Refused(c, "'first'");
  }
  SUBCASE("reduce") {
    const std::vector<std::uint8_t> flags = {1, 0, 1};
    const std::vector<std::uint32_t> values = {7, 8, 9};
    const call::Reduce ok{.reduction = Reduction::kHierarchical, .component = 64, .flags = flags, .values = values};
    Accepted(ok);
    call::Reduce c = ok;
    c.component = 0;
    Refused(c, "'component'");
    c = ok;
    c.values = In<std::uint32_t>(values).first(2);
    Refused(c, "'flags'");
    c = ok;
    c.reduction = static_cast<Reduction>(2);
    Refused(c, "'reduction'");
  }
  SUBCASE("hash") {
    const call::Hash ok{.rays = rays, .scene = &scene, .hash = {}, .quadtree_width = 0, .quadtree_depth = 0};
    Accepted(ok);
    call::Hash c = ok;
    c.quadtree_depth = 16;
    Refused(c, "'quadtree_depth'");
    c = ok;
    c.hash.light_bits = 5;  // 5 + 14 + 14 > 32
    Refused(c, "light 5");
    c = ok;
    c.hash.origin_bits = -1;
    Refused(c, "bit counts");
    c = ok;
    c.scene = nullptr;
    Refused(c, "no scene");
  }
}
