#include "rayspace/verify/pass_table.h"


#include <fmt/format.h>

#include "rayspace/verify/call_codec.h"
#include "rayspace/error.h"
#include "rayspace/pass_registry.h"

namespace rayspace::verify {
namespace {

std::uint32_t Kind(const BufferSet& in) {
  const std::uint32_t k = in.U32("kind");
  if (k > layout::kRayRefraction) ThrowInput("scalar 'kind' = {} is not a ray kind", k);
  return k;
}

// The kernel pass of a call: the registry's only owner, or, where several passes list it (raygen),
// the one its ray kind selects (rayspace/pass_registry.h lists them in kind order).
std::function<std::string(const BufferSet&)> PassOf(std::string_view call, std::set<std::string>& index_outputs) {
  std::vector<std::string> owners;
  for (const PassSpec& p : kPasses)
    for (const CallSpec& c : p.calls)
      if (c.name == call) {
        owners.emplace_back(p.name);
        for (std::string_view b : c.index_outputs) index_outputs.insert(std::string(b));
      }
  RS_CHECK_MSG(!owners.empty(), "pass table: call '{}' is not in the pass registry", call);
  if (owners.size() == 1) return [name = owners[0]](const BufferSet&) { return name; };
  return [owners](const BufferSet& in) {
    const std::uint32_t k = Kind(in);
    if (k >= owners.size()) ThrowInput("scalar 'kind' = {} selects none of {} passes", k, owners.size());
    return owners[k];
  };
}

// A call run from a buffer set: decoded, checked against its contract, run on the backend group
// that has it, its outputs moved into the set it returns.
template <typename C>
BufferSet RunFromSet(const BufferSet& in, Backends& b) {
  DecodedCall<C> d = DecodeCall<C>(in);
  emu::CheckInputs(d.call);
  if constexpr (std::is_void_v<typename C::Result>) {
    emu::RunCall(b.frame, b.hierarchy, d.call);
    return MoveOutputs(d.call, nullptr);
  } else {
    typename C::Result r = emu::RunCall(b.frame, b.hierarchy, d.call);
    return MoveOutputs(d.call, &r);
  }
}

template <typename C>
PassMethod Method() {
  PassMethod pm;
  pm.method = std::string(C::kName);
  pm.pass = PassOf(C::kName, pm.index_outputs);
  pm.run = &RunFromSet<C>;
  return pm;
}

std::vector<PassMethod> Build() {
  std::vector<PassMethod> m;
#define RS_METHOD(C) m.push_back(Method<emu::call::C>());
  RS_FRAME_CALLS(RS_METHOD)
  RS_HIERARCHY_CALLS(RS_METHOD)
#undef RS_METHOD
  return m;
}

}  // namespace

const std::vector<PassMethod>& PassMethods() {
  static const std::vector<PassMethod> kMethods = Build();
  return kMethods;
}

const PassMethod& FindPassMethod(const std::string& method) {
  std::string known;
  for (const PassMethod& m : PassMethods()) {
    if (m.method == method) return m;
    known += (known.empty() ? "" : ", ") + m.method;
  }
  ThrowInput("unknown pass method '{}'; known: {}", method, known);
}

}  // namespace rayspace::verify
