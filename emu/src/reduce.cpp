// Stream reduction of (flag, value) slots: Roger et al.'s hierarchical reduction (components of s
// slots reduced on their own, then concatenated) or a plain scan. Mirrors gpu/shaders/reduce.comp.
#include <algorithm>

#include "rayspace/emu/hierarchy.h"
#include "rayspace/emu/passes.h"
#include "rayspace/error.h"
#include "rayspace/parallel.h"
#include "rayspace/workgroup.h"

namespace rayspace::emu {

std::vector<std::uint32_t> ReduceScan(In<std::uint8_t> flags, In<std::uint32_t> values) {
  std::vector<std::uint32_t> f(flags.begin(), flags.end());
  std::uint32_t total = 0;
  const std::vector<std::uint32_t> off = ExclusiveScan(f, &total, KernelSite::Of("reduce"));
  std::vector<std::uint32_t> out(total);
  ParallelFor(flags.size(), [&](std::size_t i) {
    if (flags[i]) out[off[i]] = values[i];
  });
  return out;
}

namespace {

// reduce.comp's Local and Concat phases: one subgroup per component, grid-stride over the components.
// Subgroups of one workgroup whose components are shorter (the last one) or missing (past the end)
// run the workgroup's rounds with inactive lanes, which add 0 to the subgroup sums and write nothing.
class SubgroupPerComponent {
 public:
  SubgroupPerComponent(const KernelSite& site, std::uint32_t n, std::uint32_t s)
      : site_(site), n_(n), s_(s), comps_((n + s - 1) / s) {
    const std::uint32_t per_group = (wg::LocalSize() + wg::SubgroupSize() - 1) / wg::SubgroupSize();
    groups_ = std::min(layout::kReduceStrideGroups, (comps_ + per_group - 1) / per_group);  // as the host launches it
  }
  std::uint32_t comps() const { return comps_; }

  // Local: each component's flagged values compacted in slot order into local[c * s ..], its count
  // into counts[c].
  void Local(In<std::uint8_t> flags, In<std::uint32_t> values, std::uint32_t* local, std::uint32_t* counts) {
    DispatchKernel(site_, "Local", groups_, [&](wg::Workgroup& w) {
      const std::uint32_t stride = groups_ * w.num_subgroups();
      wg::Private<std::uint32_t> f = w.Private<std::uint32_t>(), k = w.Private<std::uint32_t>();
      for (std::uint32_t round = 0; round * stride < comps_; ++round) {
        const auto comp = [&](const wg::Inv& i) { return w.id() * w.num_subgroups() + i.subgroup_id + round * stride; };
        const auto end = [&](const wg::Inv& i) { return std::min(n_, (comp(i) + 1) * s_); };
        w.Phase([&](wg::Inv& i) { k[i] = 0; });
        // Step `it` of each subgroup covers slots it * lanes .. of its component; a partial last
        // subgroup has the fewest lanes and the most steps.
        for (std::uint32_t it = 0; it * Lanes(w, w.num_subgroups() - 1) < s_; ++it) {
          w.Phase([&](wg::Inv& i) {
            const std::uint32_t at = it * Lanes(w, i.subgroup_id) + i.lane, slot = comp(i) * s_ + at;
            f[i] = comp(i) < comps_ && at < s_ && slot < end(i) && flags[slot] != 0 ? 1u : 0u;
          });
          const wg::Private<std::uint32_t> before = w.SubgroupExclusiveAdd(f), sum = w.SubgroupAdd(f);
          w.Phase([&](wg::Inv& i) {
            if (f[i]) local[comp(i) * s_ + k[i] + before[i]] = values[comp(i) * s_ + it * Lanes(w, i.subgroup_id) + i.lane];
            k[i] += sum[i];
          });
        }
        const wg::Private<bool> elect = w.SubgroupElect();
        w.Phase([&](wg::Inv& i) {
          if (elect[i] && comp(i) < comps_) counts[comp(i)] = k[i];
        });
      }
    });
  }

  // Concat: each component's segment to its offset (offsets[c], the total after the last).
  void Concat(const std::uint32_t* local, const std::vector<std::uint32_t>& offsets, std::uint32_t total, std::uint32_t* out) {
    DispatchKernel(site_, "Concat", groups_, [&](wg::Workgroup& w) {
      const std::uint32_t stride = groups_ * w.num_subgroups();
      w.Phase([&](wg::Inv& i) {
        const std::uint32_t lanes = Lanes(w, i.subgroup_id);
        for (std::uint32_t c = w.id() * w.num_subgroups() + i.subgroup_id; c < comps_; c += stride) {
          const std::uint32_t next = c + 1 < comps_ ? offsets[c + 1] : total;
          for (std::uint32_t k = i.lane; k < next - offsets[c]; k += lanes) out[offsets[c] + k] = local[c * s_ + k];
        }
      });
    });
  }

 private:
  // The lanes of subgroup `sg` (GLSL: subgroupBallotBitCount(subgroupBallot(true))): the last
  // subgroup is partial when the local size is not a multiple of the subgroup size.
  static std::uint32_t Lanes(const wg::Workgroup& w, std::uint32_t sg) {
    return std::min(w.subgroup_size(), w.local_size() - sg * w.subgroup_size());
  }
  KernelSite site_;
  std::uint32_t n_, s_, comps_, groups_ = 0;
};

}  // namespace

std::vector<std::uint32_t> ReduceHierarchical(In<std::uint8_t> flags, In<std::uint32_t> values, int component) {
  // Roger et al. §4.1: reduce each component of s slots on its own, then concatenate the segments
  // at offsets given by a scan of the per-component counts.
  const KernelSite site = KernelSite::Of("reduce");
  RS_CHECK_MSG(flags.size() < 0xffffffffull && component >= 1, "reduce: {} slots, component {}", flags.size(), component);
  SubgroupPerComponent sub(site, static_cast<std::uint32_t>(flags.size()), static_cast<std::uint32_t>(component));
  std::vector<std::uint32_t> local(flags.size()), counts(sub.comps());
  sub.Local(flags, values, local.data(), counts.data());
  std::uint32_t total = 0;
  const std::vector<std::uint32_t> off = ExclusiveScan(counts, &total, site);
  std::vector<std::uint32_t> out(total);
  sub.Concat(local.data(), off, total, out.data());
  return out;
}

std::vector<std::uint32_t> PassReduce(const call::Reduce& c) {
  return c.reduction == Reduction::kHierarchical ? ReduceHierarchical(c.flags, c.values, c.component)
                                                 : ReduceScan(c.flags, c.values);
}

}  // namespace rayspace::emu
