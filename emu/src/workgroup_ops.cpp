// C++ mirrors of gpu/shaders/workgroup.glsl on the workgroup model, phase for phase: a subgroup
// operation or a barrier in the GLSL is a phase boundary here, and nowhere else.
#include "rayspace/emu/workgroup_ops.h"

#include <algorithm>

#include "rayspace/contract.h"
#include "rayspace/error.h"
#include "rayspace/settings.h"

namespace rayspace::emu {
namespace {

}  // namespace

bool AnyEmuFault() { return !CurrentSettings().emu_faults.empty(); }

std::uint32_t EmuFault(std::string_view pass) {
  const auto& faults = CurrentSettings().emu_faults;
  auto it = faults.find(pass);
  return it == faults.end() ? 0u : it->second;
}

bool WorkgroupModel() { return CurrentSettings().workgroup_model; }
bool RunsWorkgroupMirror(std::string_view pass) { return WorkgroupModel() || EmuFault(pass) != 0; }

void DispatchKernel(const KernelSite& site, std::string_view phase, std::uint32_t groups,
                    const std::function<void(wg::Workgroup&)>& kernel) {
  if (groups == 0) return;
  wg::DispatchOptions o;
  o.throw_on_report = true;
  wg::Dispatch(std::string(site.pass) + "." + std::string(phase), groups, wg::LocalSize(), kernel, o);
}

wg::Shared<std::uint32_t>& WorkgroupTile(wg::Workgroup& w) {
  return w.Shared<std::uint32_t>(w.local_size(), "wg_tile");
}

wg::Private<std::uint32_t> WorkgroupInclusiveAdd(wg::Workgroup& w, wg::Shared<std::uint32_t>& tile,
                                                 const wg::Private<std::uint32_t>& v, wg::Private<std::uint32_t>& total,
                                                 std::uint32_t fault) {
  const wg::Private<std::uint32_t> inclusive = w.SubgroupInclusiveAdd(v);
  const wg::Private<std::uint32_t> subgroup_sum = w.SubgroupAdd(v);
  const wg::Private<bool> elect = w.SubgroupElect();
  // kFaultSubgroup32: subgroups taken as 32 lanes wide whatever the device's width.
  const bool wide = fault == layout::kFaultSubgroup32;
  const std::uint32_t num_subgroups = wide ? (w.local_size() + 31u) / 32u : w.num_subgroups();
  const auto subgroup = [wide](const wg::Inv& i) { return wide ? i.local_id / 32u : i.subgroup_id; };
  const std::uint32_t shift = fault == layout::kFaultSharedOffByOne ? 1u : 0u;
  const auto publish = [&](wg::Inv& i) {
    if (elect[i]) tile[subgroup(i) + shift] = subgroup_sum[i];
  };
  wg::Private<std::uint32_t> out = w.Private<std::uint32_t>();
  const auto combine = [&](wg::Inv& i) {
    std::uint32_t before = 0, all = 0;
    for (std::uint32_t k = 0; k < num_subgroups; ++k) {
      const std::uint32_t x = tile[k];
      before += k < subgroup(i) ? x : 0u;
      all += x;
    }
    total[i] = all;
    out[i] = before + inclusive[i];
  };
  if (fault == layout::kFaultDroppedBarrier) {
    w.Phase([&](wg::Inv& i) { publish(i), combine(i); });
  } else if (fault == layout::kFaultDivergentBarrier) {
    w.Phase([&](wg::Inv& i) {
      publish(i);
      if (i.local_id < w.local_size() / 2u) w.Barrier();
      combine(i);
    });
  } else {
    w.Phase(publish);
    w.Barrier();
    w.Phase(combine);
  }
  w.Barrier();  // the tile is free for the next call
  return out;
}

wg::Private<std::uint32_t> WorkgroupRank(wg::Workgroup& w, wg::Shared<std::uint32_t>& tile) {
  const wg::Private<bool> elect = w.SubgroupElect();
  wg::Private<std::uint32_t> rank = w.Private<std::uint32_t>();
  // The model's subgroups are linear and full but the last: subgroupBallotBitCount is the lanes
  // there, subgroupBallotExclusiveBitCount the lane.
  const auto lanes = [&](std::uint32_t sg) { return std::min(w.subgroup_size(), w.local_size() - sg * w.subgroup_size()); };
  const std::uint32_t top = w.local_size() - 1;  // the counts fill the tile from its top, as the kernel's
  w.Phase([&](wg::Inv& i) {
    if (elect[i]) tile[top - i.subgroup_id] = lanes(i.subgroup_id);
  });
  w.Barrier();
  w.Phase([&](wg::Inv& i) {
    std::uint32_t before = 0;
    for (std::uint32_t k = 0; k < i.subgroup_id; ++k) before += tile[top - k];
    rank[i] = before + i.lane;
  });
  w.Barrier();  // the tile is free for the scans
  return rank;
}

wg::Private<std::uint32_t> WorkgroupSum(wg::Workgroup& w, wg::Shared<std::uint32_t>& tile,
                                        const std::function<std::uint32_t(std::uint32_t)>& load, std::uint32_t i0,
                                        std::uint32_t i1, std::uint32_t fault) {
  wg::Private<std::uint32_t> s = w.Private<std::uint32_t>(), total = w.Private<std::uint32_t>();
  const std::uint32_t step = w.local_size();
  w.Phase([&](wg::Inv& i) {
    std::uint32_t x = 0;
    for (std::uint32_t k = i0 + i.local_id; k < i1; k += step) x += load(k);
    s[i] = x;
  });
  WorkgroupInclusiveAdd(w, tile, s, total, fault);
  return total;
}

std::uint32_t WorkgroupScanInPlace(wg::Workgroup& w, wg::Shared<std::uint32_t>& tile, std::uint32_t* buf,
                                   std::uint32_t count, const wg::Private<std::uint32_t>& rank, std::uint32_t fault) {
  const std::uint32_t step = w.local_size();
  wg::Private<std::uint32_t> v = w.Private<std::uint32_t>(), chunk = w.Private<std::uint32_t>();
  std::uint32_t carry = 0;  // uniform: every invocation holds the same
  for (std::uint32_t c0 = 0; c0 < count; c0 += step) {
    w.Phase([&](wg::Inv& i) {
      const std::uint32_t k = c0 + rank[i];
      v[i] = k < count ? buf[k] : 0u;
    });
    const wg::Private<std::uint32_t> inc = WorkgroupInclusiveAdd(w, tile, v, chunk, fault);
    w.Phase([&](wg::Inv& i) {
      const std::uint32_t k = c0 + rank[i];
      if (k < count) buf[k] = carry + (inc[i] - v[i]);
    });
    carry += chunk[0u];
  }
  return carry;
}

std::uint32_t ReduceThenScan(const KernelSite& site, std::size_t n, const std::function<std::uint32_t(std::size_t)>& flag,
                             const std::function<void(std::size_t, std::uint32_t)>& slot,
                             const std::function<void(std::uint32_t)>& total) {
  constexpr std::uint32_t kBlock = layout::kScanBlock;
  RS_CHECK_MSG(n < 0xffffffffull, "{}: a stream of {} elements does not fit 32-bit offsets", site.pass, n);
  const auto count = static_cast<std::uint32_t>(n);
  const std::uint32_t blocks = (count + kBlock - 1) / kBlock;
  std::vector<std::uint32_t> sums(blocks + 1, 0);  // per block, then the total
  DispatchKernel(site, "BlockSums", blocks, [&](wg::Workgroup& w) {
    auto& tile = WorkgroupTile(w);
    const std::uint32_t g = w.id();
    const wg::Private<std::uint32_t> total = WorkgroupSum(
        w, tile, [&](std::uint32_t i) { return flag(i); }, g * kBlock, std::min(count, (g + 1) * kBlock), site.fault);
    w.Phase([&](wg::Inv& i) {
      if (i.local_id == 0) sums[g] = total[i];
    });
  });
  DispatchKernel(site, "ScanSums", blocks ? 1u : 0u, [&](wg::Workgroup& w) {
    auto& tile = WorkgroupTile(w);
    const std::uint32_t total = WorkgroupScanInPlace(w, tile, sums.data(), blocks, WorkgroupRank(w, tile), site.fault);
    w.Phase([&](wg::Inv& i) {
      if (i.local_id == 0) sums[blocks] = total;
    });
  });
  if (total) total(sums[blocks]);
  DispatchKernel(site, "Scatter", blocks, [&](wg::Workgroup& w) {
    auto& tile = WorkgroupTile(w);
    const std::uint32_t g = w.id(), end = std::min(count, (g + 1) * kBlock), step = w.local_size();
    // kFaultWorkgroupOffset: the workgroup starts at the next block's offset.
    std::uint32_t run = sums[site.fault == layout::kFaultWorkgroupOffset ? g + 1 : g];
    const wg::Private<std::uint32_t> r = WorkgroupRank(w, tile);
    wg::Private<std::uint32_t> f = w.Private<std::uint32_t>(), total = w.Private<std::uint32_t>();
    for (std::uint32_t c0 = g * kBlock; c0 < end; c0 += step) {
      w.Phase([&](wg::Inv& i) { f[i] = c0 + r[i] < end ? flag(c0 + r[i]) : 0u; });
      const wg::Private<std::uint32_t> inc = WorkgroupInclusiveAdd(w, tile, f, total, site.fault);
      w.Phase([&](wg::Inv& i) {
        if (c0 + r[i] < end) slot(c0 + r[i], run + (inc[i] - f[i]));
      });
      run += total[0u];
    }
  });
  return sums[blocks];
}

}  // namespace rayspace::emu
