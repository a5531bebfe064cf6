// Implementation of bemsurg/snapshot_buffers.hpp.
#pragma once

#include "bemsurg/config.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <new>

#include "bemsurg/dense_storage.hpp"
#include "bemsurg/snapshot_buffers.hpp"

namespace bemsurg {

BEMSURG_INLINE SnapshotBufferPool::~SnapshotBufferPool() {
  for (const Held& h : held_) std::free(h.data);
}

BEMSURG_INLINE double* SnapshotBufferPool::allocate(Eigen::Index count) {
  // 64-byte aligned (a cache line; Eigen's vectorised kernels need 16 or 32), the size a multiple of it
  // as aligned_alloc requires.
  const std::size_t bytes = (static_cast<std::size_t>(std::max<Eigen::Index>(count, 1)) * sizeof(double) + 63) & ~std::size_t(63);
  auto* data = static_cast<double*>(std::aligned_alloc(64, bytes));
  if (!data) throw std::bad_alloc();
  advise_huge_pages(data, count);
  return data;
}

BEMSURG_INLINE std::shared_ptr<double> SnapshotBufferPool::owned(double* data, Eigen::Index capacity,
                                                                 const std::shared_ptr<SnapshotBufferPool>& pool) {
  std::weak_ptr<SnapshotBufferPool> home = pool;
  // Should the control block not be allocated, the constructor runs the deleter itself (the buffer
  // goes back or is freed) and rethrows: called outside the pool's lock for that reason.
  return std::shared_ptr<double>(data, [home, capacity](double* p) {
    if (const std::shared_ptr<SnapshotBufferPool> to = home.lock())
      to->give_back(p, capacity);
    else
      std::free(p);
  });
}

BEMSURG_INLINE std::shared_ptr<double> SnapshotBufferPool::fresh(Eigen::Index count) { return owned(allocate(count), count, nullptr); }

BEMSURG_INLINE std::shared_ptr<double> SnapshotBufferPool::acquire(Eigen::Index count) {
  std::shared_ptr<SnapshotBufferPool> self = shared_from_this();
  Held found{nullptr, 0};
  {
    std::lock_guard<std::mutex> lock(mutex_);
    auto best = held_.end();
    for (auto it = held_.begin(); it != held_.end(); ++it)
      if (it->capacity >= count && (best == held_.end() || it->capacity < best->capacity)) best = it;
    if (best != held_.end()) {
      found = *best;
      held_.erase(best);
      ++reused_;
    }
  }
  if (found.data) return owned(found.data, found.capacity, self);  // outside the lock: see owned()
  const Eigen::Index capacity = with_slack(count);
  double* data = allocate(capacity);
  {
    std::lock_guard<std::mutex> lock(mutex_);
    ++allocated_;
  }
  return owned(data, capacity, self);
}

BEMSURG_INLINE void SnapshotBufferPool::reserve(Eigen::Index count, std::size_t buffers) {
  buffers = std::min(buffers, max_buffers_);
  std::size_t missing = 0;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    std::size_t fitting = 0;
    for (const Held& h : held_) fitting += h.capacity >= count ? 1 : 0;
    missing = buffers > fitting ? buffers - fitting : 0;
  }
  const Eigen::Index capacity = with_slack(count);
  for (std::size_t i = 0; i < missing; ++i) {
    double* data = allocate(capacity);
    std::fill(data, data + capacity, 0.0);  // the first touches, now
    give_back(data, capacity);              // beyond the pool's size the smallest goes
  }
}

BEMSURG_INLINE void SnapshotBufferPool::give_back(double* data, Eigen::Index capacity) {
  double* drop = data;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (max_buffers_ > 0) {
      held_.push_back(Held{data, capacity});
      drop = nullptr;
      if (held_.size() > max_buffers_) {  // full: the smallest goes (a chain's tables grow)
        auto smallest = std::min_element(held_.begin(), held_.end(), [](const Held& a, const Held& b) { return a.capacity < b.capacity; });
        drop = smallest->data;
        held_.erase(smallest);
      }
    }
  }
  std::free(drop);  // outside the lock
}

BEMSURG_INLINE SnapshotBufferPool::Counts SnapshotBufferPool::counts() const {
  std::lock_guard<std::mutex> lock(mutex_);
  Counts c;
  c.reused = reused_;
  c.allocated = allocated_;
  c.held = held_.size();
  for (const Held& h : held_) c.held_bytes += static_cast<double>(h.capacity) * sizeof(double);
  return c;
}

}  // namespace bemsurg
