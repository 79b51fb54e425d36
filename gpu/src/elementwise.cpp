// The host side of every element-wise pass (rayspace/contract.h, "element-wise passes"): the call's
// input arrays are bound in field order, the result after them, and the kernel runs one invocation per
// element, in parts that fit one binding. A new element-wise pass needs no launch code of its own.
#include <type_traits>

#include "kernel_util.h"
#include "rayspace/gpu/passes.h"

namespace rayspace::gpu_backend {
using namespace detail;
namespace {

template <typename T> struct SpanElem { static constexpr bool kIs = false; };
template <typename T> struct SpanElem<std::span<const T>> { static constexpr bool kIs = true; using Type = T; };

// The kernel's element of a result: results narrower than a word are written as uints.
template <typename R>
using KernelElem = std::conditional_t<(sizeof(R) < 4), std::uint32_t, R>;

}  // namespace

template <typename C>
vk::Status VulkanPasses::Elementwise(const C& call, VulkanOut<C>& out) {
  using R = typename C::Result::value_type;
  constexpr std::optional<PassId> id = PassOfCall(C::kName);
  static_assert(id.has_value(), "an element-wise call must be listed by a registered pass");
  constexpr std::string_view kPush = Pass(*id).push_type;
  static_assert(kPush == "ElementwisePush", "an element-wise pass pushes ElementwisePush");
  // Inputs: every field an array of the same length.
  std::size_t n = 0, inputs = 0, widest = sizeof(KernelElem<R>);
  bool same = true;
  emu::ForEachField(call, [&](std::string_view, const auto& f) {
    using F = std::decay_t<decltype(f)>;
    static_assert(SpanElem<F>::kIs, "an element-wise call holds only input arrays");
    if (inputs++ == 0) n = f.size();
    same &= f.size() == n;
    widest = std::max(widest, sizeof(typename SpanElem<F>::Type));
  });
  if (!same) return vk::Status::Fail(fmt::format("{}: input arrays differ in length", C::kName));
  if (Pass(*id).bindings != inputs + 1)
    return vk::Status::Fail(fmt::format("{}: the pass has {} bindings, the call {} inputs and a result", C::kName,
                                        Pass(*id).bindings, inputs));
  vk::Context& c = *ctx_;
  std::vector<KernelElem<R>> wide(n);
  Keep keep;
  vk::Recorder rec(c);
  RS_TRY(ForParts(n, PerPart(widest), extra_dispatches_, [&](std::size_t i0, std::size_t i1) -> vk::Status {
    std::vector<const vk::Buffer*> b;
    vk::Status st = vk::Status::Ok();
    emu::ForEachField(call, [&](std::string_view, const auto& f) {
      const vk::Buffer* buf = nullptr;
      if (st) st = keep.From(c, Slice(f, i0, i1), buf);
      b.push_back(buf);
    });
    RS_TRY(st);
    const vk::Buffer* result = nullptr;
    RS_TRY(keep.Output(c, (i1 - i0) * sizeof(KernelElem<R>), result, wide.data() + i0));
    b.push_back(result);
    const layout::ElementwisePush push{static_cast<std::uint32_t>(i1 - i0), static_cast<std::uint32_t>(i0)};
    return rec.Dispatch(K(*id), b, &push, sizeof push, push.count);
  }));
  RS_TRY(rec.Submit());
  RS_TRY(keep.CopyBack());
  out.assign(wide.begin(), wide.end());  // narrows a uint per element to the result's type
  return vk::Status::Ok();
}

#define RS_ELEMENTWISE_RUN(C) \
  vk::Status VulkanPasses::Run(const emu::call::C& c, VulkanOut<emu::call::C>& out) { return Elementwise(c, out); }
RS_ELEMENTWISE_CALLS(RS_ELEMENTWISE_RUN)
#undef RS_ELEMENTWISE_RUN

}  // namespace rayspace::gpu_backend
