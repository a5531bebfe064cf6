// bemsurg/snapshot_buffers.hpp: storage for a chain of large immutable snapshots that reuses what the
// snapshots let go of leave behind. A core helper: the Green's table (presolution/) keeps its columns
// in such a buffer and a cut's table update (cutting/) draws the next snapshot's from a pool
// (docs/cutting.md, "Snapshot storage").
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <memory>
#include <mutex>
#include <vector>

namespace bemsurg {

/// Buffers of doubles for large snapshots made one after another, each immutable once published: the
/// tables of a cut's steps (docs/cutting.md, "Snapshot storage"). A fresh buffer costs its first
/// touches, one page fault per 4 KiB or a huge-page compaction, which on a virtual machine took 3 to
/// 50 times as long as the copy of an 80 MB table into memory already touched (the liver session,
/// issue 39). The pool keeps the buffers of snapshots nobody holds any more
/// and hands them out again: acquire() returns the smallest held buffer that fits, else a fresh one
/// with `slack` room to spare (a cut's next table is a little larger). When a snapshot's last owner
/// lets it go, its buffer comes back (under a mutex: the haptic loop frees its models off the haptic
/// thread, haptics/haptic_loop.hpp) or is freed when the pool is full (`max_buffers`; the smallest
/// goes first) or gone. No hidden global: one pool per chain of snapshots (CutSystemUpdate owns one).
/// \ingroup core
class SnapshotBufferPool : public std::enable_shared_from_this<SnapshotBufferPool> {
 public:
  /// What acquire() did so far.
  struct Counts {
    std::size_t reused = 0;     // buffers handed out again
    std::size_t allocated = 0;  // fresh buffers
    std::size_t held = 0;       // buffers waiting in the pool now
    double held_bytes = 0.0;
  };

  /// Use through std::make_shared (the buffers' deleters find the pool through a weak pointer).
  explicit SnapshotBufferPool(std::size_t max_buffers = 2, double slack = 1.0 / 16.0) : max_buffers_(max_buffers), slack_(slack) {
    held_.reserve(max_buffers_ + 1);  // give_back runs in deleters (noexcept): it never reallocates
  }
  SnapshotBufferPool(const SnapshotBufferPool&) = delete;
  SnapshotBufferPool& operator=(const SnapshotBufferPool&) = delete;
  ~SnapshotBufferPool();

  /// A buffer of at least `count` doubles, its entries as its last snapshot left them or uninitialised;
  /// freed, or given back to this pool, when the last copy of the pointer goes. Throws std::bad_alloc.
  std::shared_ptr<double> acquire(Eigen::Index count);
  /// Makes sure the pool holds `buffers` buffers (at most its size) of at least `count` doubles,
  /// allocating and touching what is missing now, while nothing waits for it: a chain's first steps
  /// then find touched memory too (a session that will cut reserves before its clock starts).
  /// Throws std::bad_alloc.
  void reserve(Eigen::Index count, std::size_t buffers);
  Counts counts() const;

  /// A buffer of `count` doubles owned by nobody else, freed with its last pointer (no pool), advised for
  /// huge pages as dense_storage.hpp explains.
  static std::shared_ptr<double> fresh(Eigen::Index count);

 private:
  struct Held {
    double* data;
    Eigen::Index capacity;
  };
  static double* allocate(Eigen::Index count);
  /// `count` with the pool's room to spare: the capacity of a fresh buffer.
  Eigen::Index with_slack(Eigen::Index count) const {
    return static_cast<Eigen::Index>(std::ceil(static_cast<double>(count) * (1.0 + std::max(0.0, slack_))));
  }
  static std::shared_ptr<double> owned(double* data, Eigen::Index capacity, const std::shared_ptr<SnapshotBufferPool>& pool);
  void give_back(double* data, Eigen::Index capacity);

  std::size_t max_buffers_;
  double slack_;
  mutable std::mutex mutex_;
  std::vector<Held> held_;
  std::size_t reused_ = 0, allocated_ = 0;
};

}  // namespace bemsurg

// Definitions (header-only: the numerical core needs no compiled library, docs/design.md).
#ifndef BEMSURG_SEPARATE_COMPILATION  // else compiled once by the library (bemsurg/config.hpp)
#include "bemsurg/impl/snapshot_buffers_impl.hpp"
#endif
