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
#include <memory>
#include <span>
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

// A buffer's bytes, immutable once made and shared between the sets and decoded calls that read
// them: a diff call copies each array at most once on its way in (none when the set only views the
// caller's arrays for the call's duration), and its outputs are adopted, not copied, on their way out.
class Blob {
 public:
  ElemType type = ElemType::kU32;

  Blob() = default;
  // Adopts the vector: no copy.
  template <typename T>
  static Blob Own(std::vector<T>&& v) {
    auto p = std::make_shared<std::vector<T>>(std::move(v));
    Blob b(TypeOf<T>::kType, reinterpret_cast<const std::uint8_t*>(p->data()), p->size() * sizeof(T));
    b.vector_ = true;
    b.owner_ = std::move(p);
    return b;
  }
  template <typename T>
  static Blob Copy(std::span<const T> v) { return Own(std::vector<T>(v.begin(), v.end())); }
  // Views v without owning it: the blob, and every set and decoded call reading it, must not outlive
  // v's storage or see it change.
  template <typename T>
  static Blob Borrow(std::span<const T> v) {
    return Blob(TypeOf<T>::kType, reinterpret_cast<const std::uint8_t*>(v.data()), v.size() * sizeof(T));
  }
  static Blob FromBytes(ElemType type, std::vector<std::uint8_t>&& bytes);

  std::span<const std::uint8_t> bytes() const { return {data_, size_}; }
  std::size_t count() const { return size_ / Info(type).bytes; }
  // The elements in place (the blob's type must be T's); keep owner() while the view is used.
  template <typename T>
  std::span<const T> View() const {
    RS_CHECK(type == TypeOf<T>::kType && reinterpret_cast<std::uintptr_t>(data_) % alignof(T) == 0);
    return {reinterpret_cast<const T*>(data_), size_ / sizeof(T)};
  }
  const std::shared_ptr<const void>& owner() const { return owner_; }
  // The elements as a vector: moved out when this blob alone owns a vector of them (it is left
  // empty), copied otherwise.
  template <typename T>
  std::vector<T> Take() {
    const std::span<const T> v = View<T>();
    if (vector_ && owner_.use_count() == 1) {
      std::vector<T> out = std::move(*std::const_pointer_cast<std::vector<T>>(std::static_pointer_cast<const std::vector<T>>(owner_)));
      *this = Blob(type, nullptr, 0);
      return out;
    }
    return {v.begin(), v.end()};
  }

 private:
  Blob(ElemType t, const std::uint8_t* data, std::size_t size) : type(t), data_(data), size_(size) {}
  std::shared_ptr<const void> owner_;  // null for a borrowed or empty blob
  const std::uint8_t* data_ = nullptr;
  std::size_t size_ = 0;
  bool vector_ = false;  // owner_ holds a std::vector of the type's element
};

class BufferSet {
 public:
  template <typename T>
  void Put(const std::string& name, std::span<const T> v) {
    static_assert(sizeof(T) == 1 || sizeof(T) % 4 == 0);
    blobs_[name] = Blob::Copy(v);
  }
  template <typename T>
  void Put(const std::string& name, const std::vector<T>& v) { Put(name, std::span<const T>(v)); }
  template <typename T>
  void Put(const std::string& name, std::vector<T>&& v) {
    static_assert(sizeof(T) == 1 || sizeof(T) % 4 == 0);
    blobs_[name] = Blob::Own(std::move(v));
  }
  // The set views v (see Blob::Borrow): for a set that lives only while v does.
  template <typename T>
  void PutView(const std::string& name, std::span<const T> v) {
    static_assert(sizeof(T) == 1 || sizeof(T) % 4 == 0);
    blobs_[name] = Blob::Borrow(v);
  }
  template <typename T>
  void PutOne(const std::string& name, const T& v) { Put(name, std::vector<T>{v}); }
  // Get, View and Take throw InputError when the buffer is missing or has another type (a
  // hand-edited or foreign set).
  template <typename T>
  std::vector<T> Get(const std::string& name) const {
    const std::span<const T> v = Find(name, TypeOf<T>::kType).template View<T>();
    return {v.begin(), v.end()};
  }
  // In place; the span lives as long as the blob's owner (Owner(name)) or the set.
  template <typename T>
  std::span<const T> View(const std::string& name) const { return Find(name, TypeOf<T>::kType).template View<T>(); }
  const std::shared_ptr<const void>& Owner(const std::string& name) const { return blobs_.at(name).owner(); }
  // Moves the buffer out when the set alone owns it (see Blob::Take).
  template <typename T>
  std::vector<T> Take(const std::string& name) {
    Find(name, TypeOf<T>::kType);
    return blobs_.at(name).template Take<T>();
  }
  template <typename T>
  T GetOne(const std::string& name) const {
    const std::span<const T> v = View<T>(name);
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
  // `view`: the set views the scene's arrays (see PutView).
  void PutScene(const SceneBuffers& scene, bool view = false);
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
// `actual_name` names the actual side in the comparison's text ("vulkan", "sim").
BufferComparison CompareBlobs(const std::string& pass, const std::string& name, const Blob& expected, const Blob& actual,
                              const std::string& actual_name);

}  // namespace rayspace::verify
