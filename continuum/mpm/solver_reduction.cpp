// The per-thread node accumulators of the Solver (solver.hpp) and their reduction in thread order,
// which makes a run reproduce itself bit for bit for a given thread count (docs/mpm.md,
// "Threads"). Solver::scatter and Solver::liquid_volume_sums are in solver_internal.hpp.
#include <algorithm>
#include <cstddef>

#include "continuum/mpm/solver_internal.hpp"

namespace granflow::mpm {

using namespace solver_internal;

double* Solver::scatter_buffer(int t, int fields) {
  if (threads_ == 1) {
    std::fill(acc_.begin(), acc_.begin() + static_cast<std::size_t>(fields) * nn_, 0.0);
    return acc_.data();
  }
  double* mine = scratch_.data() + static_cast<std::size_t>(NF) * nn_ * t;
  ThreadSlot& slot = slots_[t];
  for (int f = 0; f < slot.dirty_fields; ++f) {
    double* field = mine + static_cast<std::size_t>(f) * nn_;
    std::fill(field + slot.dirty_begin, field + slot.dirty_end, 0.0);
    std::fill(field, field + slot.dirty_wrap_end, 0.0);
  }
  slot.dirty_fields = slot.dirty_begin = slot.dirty_end = slot.dirty_wrap_end = 0;
  // acc_ on this thread's share: the owner's direct contributions land here, the reduction adds
  // the buffers to them.
  int b, e;
  node_share(nn_, t, threads_, b, e);
  for (int f = 0; f < fields; ++f) {
    double* out = acc_.data() + static_cast<std::size_t>(f) * nn_;
    std::fill(out + b, out + e, 0.0);
  }
  return mine;
}

void Solver::mark_dirty(int t, int fields, int begin, int end, int wrap_end) {
  if (threads_ == 1) return;
  ThreadSlot& slot = slots_[t];
  if (!(begin < end)) begin = end = 0;
  if (wrap_end >= begin) {  // the two parts meet: one interval [0, end)
    end = std::max(end, wrap_end);
    begin = 0;
    wrap_end = 0;
  }
  slot.dirty_fields = end > begin || wrap_end > 0 ? fields : 0;
  slot.dirty_begin = begin;
  slot.dirty_end = end;
  slot.dirty_wrap_end = wrap_end;
}

// Sum in a fixed order: the owner's direct contributions (zero where it wrote none), then the
// buffers in thread order, as a serial loop over the threads would: a given thread count
// reproduces itself bit for bit (which points are direct depends only on the positions). A
// buffer is zero outside the span its thread dirtied, so only that span is read (a thread's
// chunk of points touches a band of the grid, not all of it; on the polar grid the band of the
// last θ-chunk continues across the seam θ = 0 into the first rays, a second interval, so that
// the span is not the whole grid: x + 0 = x, skipping the zeros changes no sum).
void Solver::reduce_part(int fields, int t) {
  if (threads_ == 1) return;
  int b, e;
  node_share(nn_, t, threads_, b, e);
  const std::size_t stride = static_cast<std::size_t>(NF) * nn_;
  for (int f = 0; f < fields; ++f) {
    double* out = acc_.data() + static_cast<std::size_t>(f) * nn_;
    for (int u = 0; u < threads_; ++u) {
      const ThreadSlot& slot = slots_[u];
      if (f >= slot.dirty_fields) continue;
      const double* in = scratch_.data() + stride * u + static_cast<std::size_t>(f) * nn_;
      const int lo = std::max(b, slot.dirty_begin), hi = std::min(e, slot.dirty_end);
      for (int a = lo; a < hi; ++a) out[a] += in[a];
      // the part across the polar seam (disjoint from the first: each node once per thread)
      const int wrap_hi = std::min(e, slot.dirty_wrap_end);
      for (int a = b; a < wrap_hi; ++a) out[a] += in[a];
    }
  }
}

}  // namespace granflow::mpm
