// The inputs or outputs of one pass call as named, typed buffers plus JSON scalars: what the diff
// compares, what `--save-inputs` writes and what `replay` reads back.
//
// On disk a buffer set is a directory: pass.json (method, scalars, and per buffer its type and element
// count) and one raw little-endian file NAME.bin per buffer, in the std430 layout of core/layout.h.
#pragma once
#include <cstdint>
#include <algorithm>
#include <cstring>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "rayspace/compare.h"
#include "rayspace/error.h"
#include "rayspace/layout.h"
#include "rayspace/scene_buffers.h"

namespace rayspace::verify {

enum class ElemType : std::uint8_t { kU8, kU32, kU64, kF32, kVec4, kUvec4, kRay, kSurface, kNode, kTriangle, kNormals, kInfo, kMaterial, kLight, kFrame };

struct ElemInfo {
  const char* name;
  std::size_t bytes;
  std::uint32_t float_mask;  // bit k: 32-bit word k of an element holds a float
};
const ElemInfo& Info(ElemType t);

template <typename T> struct TypeOf;
template <> struct TypeOf<std::uint8_t> { static constexpr ElemType kType = ElemType::kU8; };
template <> struct TypeOf<std::uint32_t> { static constexpr ElemType kType = ElemType::kU32; };
template <> struct TypeOf<std::uint64_t> { static constexpr ElemType kType = ElemType::kU64; };
template <> struct TypeOf<float> { static constexpr ElemType kType = ElemType::kF32; };
template <> struct TypeOf<glm::vec4> { static constexpr ElemType kType = ElemType::kVec4; };
template <> struct TypeOf<glm::uvec4> { static constexpr ElemType kType = ElemType::kUvec4; };
template <> struct TypeOf<layout::Ray> { static constexpr ElemType kType = ElemType::kRay; };
template <> struct TypeOf<layout::Surface> { static constexpr ElemType kType = ElemType::kSurface; };
template <> struct TypeOf<layout::ConeNode> { static constexpr ElemType kType = ElemType::kNode; };
template <> struct TypeOf<layout::Triangle> { static constexpr ElemType kType = ElemType::kTriangle; };
template <> struct TypeOf<layout::TriangleNormals> { static constexpr ElemType kType = ElemType::kNormals; };
template <> struct TypeOf<layout::TriangleInfo> { static constexpr ElemType kType = ElemType::kInfo; };
template <> struct TypeOf<layout::Material> { static constexpr ElemType kType = ElemType::kMaterial; };
template <> struct TypeOf<layout::Light> { static constexpr ElemType kType = ElemType::kLight; };
template <> struct TypeOf<layout::FrameConstants> { static constexpr ElemType kType = ElemType::kFrame; };

struct Blob {
  ElemType type = ElemType::kU32;
  std::vector<std::uint8_t> bytes;
  std::size_t count() const { return bytes.size() / Info(type).bytes; }
};

class BufferSet {
 public:
  template <typename T>
  void Put(const std::string& name, const std::vector<T>& v) {
    static_assert(sizeof(T) == 1 || sizeof(T) % 4 == 0);
    Blob& b = blobs_[name];
    b.type = TypeOf<T>::kType;
    const auto* p = reinterpret_cast<const std::uint8_t*>(v.data());
    b.bytes.assign(p, p + v.size() * sizeof(T));
  }
  template <typename T>
  void PutOne(const std::string& name, const T& v) { Put(name, std::vector<T>{v}); }
  // Throws InputError when the buffer is missing or has another type (a hand-edited or foreign set).
  template <typename T>
  std::vector<T> Get(const std::string& name) const {
    const Blob& b = Find(name, TypeOf<T>::kType);
    std::vector<T> v(b.bytes.size() / sizeof(T));
    std::copy(b.bytes.begin(), b.bytes.begin() + static_cast<std::ptrdiff_t>(v.size() * sizeof(T)),
              reinterpret_cast<std::uint8_t*>(v.data()));
    return v;
  }
  template <typename T>
  T GetOne(const std::string& name) const {
    const std::vector<T> v = Get<T>(name);
    if (v.size() != 1) ThrowInput("{}: buffer '{}' holds {} elements, expected 1", origin_, name, v.size());
    return v[0];
  }
  bool Has(const std::string& name) const { return blobs_.count(name) != 0; }
  const std::map<std::string, Blob>& blobs() const { return blobs_; }

  // Scalars (ids, counts, options) by name; Scalar() throws InputError when missing or not a number.
  nlohmann::json scalars = nlohmann::json::object();
  double Scalar(const std::string& name) const;
  std::uint32_t U32(const std::string& name) const;

  // The scene buffers a pass reads (all of them: a saved set is self-contained).
  void PutScene(const SceneBuffers& scene);
  SceneBuffers GetScene() const;

  void Save(const std::string& dir, const std::string& method) const;
  // Reads a set written by Save; `method` receives the pass method. Throws InputError naming the file.
  static BufferSet Load(const std::string& dir, std::string& method);

 private:
  const Blob& Find(const std::string& name, ElemType type) const;
  std::map<std::string, Blob> blobs_;
  std::string origin_ = "buffer set";
};

// Bitwise comparison of two buffers of the same name (float words get ULP distances and NaN classes):
// `expected` the emulator's, `actual` the Vulkan kernels', as the comparison's text and JSON name them.
BufferComparison CompareBlobs(const std::string& pass, const std::string& name, const Blob& expected, const Blob& actual);

}  // namespace rayspace::verify
