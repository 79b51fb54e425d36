// A call (emu/calls.h) to and from a BufferSet, field by field through its RS_FIELDS: what lets the
// diff save, compare and replay every pass without restating its signature.
//
//   In<T>              <->  buffer NAME (decoded as a view into the set's blob, which DecodedCall
//                           keeps alive)
//   std::vector<T>*    <->  buffer NAME when non-null; after the call it is an output too
//   const SceneBuffers* <-> the scene.* buffers
//   layout::FrameConstants <-> a one-element buffer NAME
//   a struct with fields <-> its fields, flattened
//   std::uint64_t      <->  a one-element buffer NAME (JSON numbers hold 53 bits; and as a buffer an
//                           output count is compared like any other output, e.g. Compacted::tested)
//   integer / enum     <->  scalar NAME; float <-> scalar NAME_bits (its bit pattern, so NaNs survive)
//   std::vector<T> (in a result) <-> buffer NAME
#pragma once
#include <bit>
#include <deque>
#include <memory>
#include <string>
#include <type_traits>

#include "rayspace/emu/calls.h"
#include "rayspace/verify/buffer_set.h"

namespace rayspace::verify {
namespace codec_detail {

template <typename T> struct IsSpan : std::false_type {};
template <typename T> struct IsSpan<std::span<const T>> : std::true_type { using Elem = T; };
template <typename T> struct IsVector : std::false_type {};
template <typename T> struct IsVector<std::vector<T>> : std::true_type { using Elem = T; };
// An unzeroed vector (emu::UninitVector: Compacted's pairs) travels as its elements.
template <typename T> struct IsUninitVector : std::false_type {};
template <typename T> struct IsUninitVector<emu::UninitVector<T>> : std::true_type { using Elem = T; };
template <typename T> struct IsVectorPtr : std::false_type {};
template <typename T> struct IsVectorPtr<std::vector<T>*> : std::true_type { using Elem = T; };

template <typename T>
constexpr bool kScalar = std::is_integral_v<T> || std::is_enum_v<T>;

// The decoded buffers and blobs a call's views point into.
class Store {
 public:
  template <typename T>
  T& Keep(T&& v) {
    auto p = std::make_shared<std::decay_t<T>>(std::forward<T>(v));
    T& r = *p;
    kept_.push_back(std::move(p));
    return r;
  }
  void KeepAlive(const std::shared_ptr<const void>& owner) {
    if (owner) kept_.push_back(owner);
  }

 private:
  std::deque<std::shared_ptr<const void>> kept_;
};

// How an encoding holds a struct's arrays: copies them (a set that outlives the struct), views them
// (a set used only while the struct's arrays live unchanged), or adopts them (the struct's vectors
// and in-place arrays are moved out and left empty).
enum class Hold { kCopy, kView, kMove };

template <Hold H, typename S>
void Encode(BufferSet& out, S& s);
template <typename S>
void Decode(const BufferSet& in, S& s, Store& store);

// From a const set a copy; from one given up, moved out where the set alone owns it.
template <typename T, typename Set>
std::vector<T> TakeOrGet(Set& in, const std::string& name) {
  if constexpr (std::is_const_v<Set>) return in.template Get<T>(name);
  else return in.template Take<T>(name);
}

template <Hold H, typename T>
void PutArray(BufferSet& out, const std::string& name, std::conditional_t<H == Hold::kMove, std::vector<T>&, const std::vector<T>&> v) {
  if constexpr (H == Hold::kMove) out.Put(name, std::move(v));
  else if constexpr (H == Hold::kView) out.PutView(name, std::span<const T>(v));
  else out.Put(name, std::span<const T>(v));
}

template <Hold H, typename F>
void EncodeField(BufferSet& out, std::string_view name_view, F& f) {
  using V = std::remove_const_t<F>;
  const std::string name(name_view);
  if constexpr (IsSpan<V>::value) {
    if constexpr (H == Hold::kView) out.PutView(name, f);
    else out.Put(name, f);
  } else if constexpr (IsVector<V>::value) {
    PutArray<H, typename IsVector<V>::Elem>(out, name, f);
  } else if constexpr (IsUninitVector<V>::value) {
    using T = typename IsUninitVector<V>::Elem;
    if constexpr (H == Hold::kView) out.PutView(name, std::span<const T>(f));
    else out.Put(name, std::span<const T>(f));
  } else if constexpr (IsVectorPtr<V>::value) {
    if (f) PutArray<H, typename IsVectorPtr<V>::Elem>(out, name, *f);
  } else if constexpr (std::is_same_v<V, const SceneBuffers*>) {
    if (f) out.PutScene(*f, H == Hold::kView);
  } else if constexpr (std::is_same_v<V, layout::FrameConstants>) {
    out.PutOne(name, f);
  } else if constexpr (std::is_same_v<V, float>) {
    out.scalars[name + "_bits"] = std::bit_cast<std::uint32_t>(f);
  } else if constexpr (std::is_same_v<V, bool>) {
    out.scalars[name] = f ? 1 : 0;
  } else if constexpr (std::is_same_v<V, std::uint64_t>) {
    out.PutOne(name, f);
  } else if constexpr (std::is_enum_v<V>) {
    out.scalars[name] = static_cast<std::underlying_type_t<V>>(f);
  } else if constexpr (kScalar<V>) {
    out.scalars[name] = f;
  } else {
    static_assert(emu::HasFields<V>, "a call field the codec does not know");
    Encode<H>(out, f);
  }
}

template <typename F>
void DecodeField(const BufferSet& in, std::string_view name_view, F& f, Store& store) {
  const std::string name(name_view);
  if constexpr (IsSpan<F>::value) {
    f = in.View<typename IsSpan<F>::Elem>(name);
    store.KeepAlive(in.Owner(name));
  } else if constexpr (IsVector<F>::value) {
    f = in.Get<typename IsVector<F>::Elem>(name);
  } else if constexpr (IsUninitVector<F>::value) {
    const auto v = in.Get<typename IsUninitVector<F>::Elem>(name);
    f.assign(v.begin(), v.end());
  } else if constexpr (IsVectorPtr<F>::value) {
    f = in.Has(name) ? &store.Keep(in.Get<typename IsVectorPtr<F>::Elem>(name)) : nullptr;
  } else if constexpr (std::is_same_v<F, const SceneBuffers*>) {
    f = &store.Keep(in.GetScene());
  } else if constexpr (std::is_same_v<F, layout::FrameConstants>) {
    f = in.GetOne<layout::FrameConstants>(name);
  } else if constexpr (std::is_same_v<F, float>) {
    f = std::bit_cast<float>(in.U32(name + "_bits"));
  } else if constexpr (std::is_same_v<F, bool>) {
    f = in.U32(name) != 0;
  } else if constexpr (std::is_same_v<F, std::uint64_t>) {
    f = in.GetOne<std::uint64_t>(name);
  } else if constexpr (std::is_enum_v<F>) {
    f = static_cast<F>(in.U32(name));
  } else if constexpr (std::is_signed_v<F> && kScalar<F>) {
    const double v = in.Scalar(name);
    if (!(v >= -2147483648.0 && v <= 2147483647.0) || v != static_cast<double>(static_cast<F>(v)))
      ThrowInput("scalar '{}' = {} is not an integer in range", name, v);
    f = static_cast<F>(v);
  } else if constexpr (kScalar<F>) {
    f = static_cast<F>(in.U32(name));
  } else {
    static_assert(emu::HasFields<F>, "a call field the codec does not know");
    Decode(in, f, store);
  }
}

template <Hold H, typename S>
void Encode(BufferSet& out, S& s) {
  emu::ForEachField(s, [&](std::string_view name, auto& f) { EncodeField<H>(out, name, f); });
}

template <typename S>
void Decode(const BufferSet& in, S& s, Store& store) {
  emu::ForEachField(s, [&](std::string_view name, auto& f) { DecodeField(in, name, f, store); });
}

// The in-place arrays (std::vector<T>*) of a call, as outputs.
template <Hold H, typename C>
void EncodeInOut(BufferSet& out, const C& c) {
  emu::ForEachField(c, [&](std::string_view name, const auto& f) {
    if constexpr (IsVectorPtr<std::decay_t<decltype(f)>>::value) EncodeField<H>(out, name, f);
  });
}
// Set is const BufferSet (the arrays are copied) or BufferSet (moved out where the set owns them).
template <typename Set, typename C>
void DecodeInOut(Set& in, const C& c) {
  emu::ForEachField(c, [&](std::string_view name, const auto& f) {
    using F = std::decay_t<decltype(f)>;
    if constexpr (IsVectorPtr<F>::value)
      if (f) *f = TakeOrGet<typename IsVectorPtr<F>::Elem>(in, std::string(name));
  });
}

// Calls f(name, first byte, bytes, element bytes) for each array and 64-bit count of a struct.
template <typename S, typename F>
void ForEachRange(const S& s, F&& f) {
  emu::ForEachField(s, [&](std::string_view name, const auto& v) {
    using V = std::decay_t<decltype(v)>;
    if constexpr (IsVector<V>::value || IsUninitVector<V>::value) {
      f(name, static_cast<const void*>(v.data()), v.size() * sizeof(typename V::value_type), sizeof(typename V::value_type));
    } else if constexpr (std::is_same_v<V, std::uint64_t>) {
      f(name, static_cast<const void*>(&v), sizeof v, sizeof v);
    } else if constexpr (emu::HasFields<V>) {
      ForEachRange(v, f);
    }
  });
}

}  // namespace codec_detail

// A call decoded from a buffer set, with the storage its views point into.
template <typename C>
struct DecodedCall {
  C call;
  codec_detail::Store store;
};

template <typename C>
BufferSet EncodeCall(const C& c) {
  BufferSet out;
  codec_detail::Encode<codec_detail::Hold::kCopy>(out, c);
  return out;
}

// The call's inputs as a set that views the call's arrays (and scene) instead of copying them: for a
// set used, and decoded calls run, only while those arrays live unchanged (the diff's calls).
template <typename C>
BufferSet ViewCall(const C& c) {
  BufferSet out;
  codec_detail::Encode<codec_detail::Hold::kView>(out, c);
  return out;
}

template <typename C>
DecodedCall<C> DecodeCall(const BufferSet& in) {
  DecodedCall<C> d;
  codec_detail::Decode(in, d.call, d.store);
  return d;
}

// A call's outputs: its result (under C::kResult for an array) and its in-place arrays.
template <typename C>
BufferSet EncodeOutputs(const C& c, const typename C::Result* result) {
  BufferSet out;
  if constexpr (codec_detail::IsVector<typename C::Result>::value) out.Put(std::string(C::kResult), *result);
  else if constexpr (!std::is_void_v<typename C::Result>) codec_detail::Encode<codec_detail::Hold::kCopy>(out, *result);
  codec_detail::EncodeInOut<codec_detail::Hold::kCopy>(out, c);
  return out;
}

// EncodeOutputs without copies: the result's arrays and the call's in-place arrays are moved into
// the set and left empty.
template <typename C>
BufferSet MoveOutputs(const C& c, typename C::Result* result) {
  BufferSet out;
  if constexpr (codec_detail::IsVector<typename C::Result>::value) out.Put(std::string(C::kResult), std::move(*result));
  else if constexpr (!std::is_void_v<typename C::Result>) codec_detail::Encode<codec_detail::Hold::kMove>(out, *result);
  codec_detail::EncodeInOut<codec_detail::Hold::kMove>(out, c);
  return out;
}

// Where a call's outputs are in memory now, named as EncodeOutputs names them: f(name, first byte,
// bytes, element bytes) for its result's arrays (and 64-bit counts) and its in-place arrays. `result`
// is null for a call without one. What `rayspace export` uses to tell where a read-back lands.
template <typename C, typename R, typename F>
void ForEachOutputRange(const C& c, const R* result, F&& f) {
  if constexpr (codec_detail::IsVector<R>::value) {
    f(C::kResult, static_cast<const void*>(result->data()), result->size() * sizeof(typename R::value_type),
      sizeof(typename R::value_type));
  } else if constexpr (emu::HasFields<R>) {
    codec_detail::ForEachRange(*result, f);
  }
  emu::ForEachField(c, [&](std::string_view name, const auto& v) {
    using V = std::decay_t<decltype(v)>;
    if constexpr (codec_detail::IsVectorPtr<V>::value)
      if (v) f(name, static_cast<const void*>(v->data()), v->size() * sizeof(typename codec_detail::IsVectorPtr<V>::Elem),
               sizeof(typename codec_detail::IsVectorPtr<V>::Elem));
  });
}

namespace codec_detail {

// A result struct's fields (arrays, 64-bit counts, nested structs) from a set, copied or moved out.
template <typename Set, typename R>
void DecodeResult(Set& in, R& r) {
  emu::ForEachField(r, [&](std::string_view name_view, auto& f) {
    using F = std::decay_t<decltype(f)>;
    const std::string name(name_view);
    if constexpr (IsVector<F>::value) {
      f = TakeOrGet<typename IsVector<F>::Elem>(in, name);
    } else if constexpr (emu::HasFields<F>) {
      DecodeResult(in, f);
    } else {
      Store unused;
      DecodeField(in, name, f, unused);
    }
  });
}

template <typename Set, typename C>
typename C::Result DecodeOutputsFrom(Set& out, const C& c) {
  DecodeInOut(out, c);
  using R = typename C::Result;
  if constexpr (IsVector<R>::value) {
    return TakeOrGet<typename IsVector<R>::Elem>(out, std::string(C::kResult));
  } else if constexpr (!std::is_void_v<R>) {
    R r;
    DecodeResult(out, r);
    return r;
  }
}

}  // namespace codec_detail

// Reads a call's result from its outputs and updates its in-place arrays: copied from a set that
// stays, moved out of one given up (where the set alone owns them).
template <typename C>
typename C::Result DecodeOutputs(const BufferSet& out, const C& c) {
  return codec_detail::DecodeOutputsFrom(out, c);
}
template <typename C>
typename C::Result DecodeOutputs(BufferSet&& out, const C& c) {
  return codec_detail::DecodeOutputsFrom(out, c);
}

}  // namespace rayspace::verify
