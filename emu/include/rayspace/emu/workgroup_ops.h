// The emulator's side of the workgroup kernels: C++ mirrors of gpu/shaders/workgroup.glsl's building
// blocks on the workgroup model (rayspace/workgroup.h), the reduce-then-scan that trim, compress,
// decompress and reduce share, and the planted faults of the emulator side (`--inject PASS:FAULT@emu`).
#pragma once
#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <string_view>

#include "rayspace/emu/streams.h"
#include "rayspace/workgroup.h"

namespace rayspace::emu {

// Planted faults of the emulated kernels (Settings::emu_faults): pass name -> fault number (the
// registry's numbers, as the kernel side's); empty by default.
std::uint32_t EmuFault(std::string_view pass);
bool AnyEmuFault();

// Whether the run asks for the emulated kernels' workgroups (Settings::workgroup_model): the commands set it when the checker is
// on, the schedule is not forward or a fault is planted with @emu (frame/src/kernel_model.cpp). A pass
// whose emulation has a faster path than its workgroup mirror (traverse.compact's lanes) takes the
// mirror then, since the faster path has no workgroups to check, reorder or plant a fault in.
// Off by default, so that library users and renders get the fast path.
bool WorkgroupModel();
// Whether `pass` runs its workgroup mirror: the model is asked for, or a fault is planted in it.
bool RunsWorkgroupMirror(std::string_view pass);

// The pass an emulated kernel runs for (its name labels the dispatches, "trim.Scatter") and its
// planted fault (0 = none).
struct KernelSite {
  std::string_view pass;
  std::uint32_t fault = 0;
  static KernelSite Of(std::string_view pass) { return {pass, EmuFault(pass)}; }
};

// wg::Dispatch of an emulated kernel phase named "<pass>.<phase>" with the emulator's local size and
// subgroup size (Settings::local_size, Settings::subgroup_size). With checking on, a checker report throws
// wg::CheckError naming the dispatch, workgroup, phase, shared word and invocations.
void DispatchKernel(const KernelSite& site, std::string_view phase, std::uint32_t groups,
                    const std::function<void(wg::Workgroup&)>& kernel);

// `shared uint wg_tile[kLocalSize]` of workgroup.glsl, declared in a kernel mirror's workgroup.
wg::Shared<std::uint32_t>& WorkgroupTile(wg::Workgroup& w);

// uint WorkgroupRank(): each invocation's rank, the order the scans add in (subgroups in order, then
// their active lanes); on the model's linear, full subgroups the local index. Two barriers.
wg::Private<std::uint32_t> WorkgroupRank(wg::Workgroup& w, wg::Shared<std::uint32_t>& tile);

// uint WorkgroupInclusiveAdd(uint v, out uint total): the inclusive prefix sum of v over the
// workgroup in rank order, and the sum of all in `total`. Ends with a barrier.
wg::Private<std::uint32_t> WorkgroupInclusiveAdd(wg::Workgroup& w, wg::Shared<std::uint32_t>& tile,
                                                 const wg::Private<std::uint32_t>& v, wg::Private<std::uint32_t>& total,
                                                 std::uint32_t fault);

// WORKGROUP_SUM: the sum of load(i) for i in [i0, i1), strided over the workgroup's invocations.
wg::Private<std::uint32_t> WorkgroupSum(wg::Workgroup& w, wg::Shared<std::uint32_t>& tile,
                                        const std::function<std::uint32_t(std::uint32_t)>& load, std::uint32_t i0,
                                        std::uint32_t i1, std::uint32_t fault);

// WORKGROUP_SCAN_IN_PLACE: exclusive scan of buf[0 .. count) in place, kLocalSize words at a time with
// a running carry, invocation i taking slots c0 + rank[i]; returns the sum.
std::uint32_t WorkgroupScanInPlace(wg::Workgroup& w, wg::Shared<std::uint32_t>& tile, std::uint32_t* buf,
                                   std::uint32_t count, const wg::Private<std::uint32_t>& rank, std::uint32_t fault);

// Order-preserving reduce-then-scan over blocks of kScanBlock flags, the three dispatches of
// trim.comp (BlockSums, ScanSums, Scatter): `flag(i)` is 0 or 1 (or a count), and `slot(i, s)` runs for
// every i in [0, n) inside the Scatter phase with s the exclusive prefix sum of the flags before i;
// `total`, if given, receives the sum between ScanSums and Scatter (as the host reads it to size the
// dense output). Returns the total. The Scatter phase's workgroup offset is where
// kFaultWorkgroupOffset is planted.
std::uint32_t ReduceThenScan(const KernelSite& site, std::size_t n, const std::function<std::uint32_t(std::size_t)>& flag,
                             const std::function<void(std::size_t, std::uint32_t)>& slot,
                             const std::function<void(std::uint32_t)>& total = {});

}  // namespace rayspace::emu
