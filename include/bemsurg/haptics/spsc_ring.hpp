// bemsurg/haptics/spsc_ring.hpp: a bounded single-producer / single-consumer queue for events and
// trace samples leaving the haptic thread (button edges, one sample per tick) and for pointers
// travelling between it and the simulation side. Capacity is fixed at construction; push and pop
// never wait or allocate; a full queue refuses the push (the caller counts it).
#pragma once

#include <atomic>
#include <cstddef>
#include <vector>

namespace bemsurg::haptics {

/// A bounded single-producer / single-consumer queue for events, trace samples and pointers leaving or reaching the haptic
/// thread. Capacity is fixed at construction; push and pop never wait or allocate, and a full queue refuses the push.
/// \ingroup haptics
template <class T>
class SpscRing {
 public:
  explicit SpscRing(std::size_t capacity) : slots_(capacity + 1) {}
  std::size_t capacity() const { return slots_.size() - 1; }

  /// Producer: false (nothing stored) when full.
  bool push(const T& value) noexcept {
    const std::size_t head = head_.load(std::memory_order_relaxed);
    const std::size_t next = head + 1 == slots_.size() ? 0 : head + 1;
    if (next == tail_.load(std::memory_order_acquire)) return false;
    slots_[head] = value;
    head_.store(next, std::memory_order_release);
    return true;
  }
  /// Producer: whether a push would succeed now.
  bool full() const noexcept {
    const std::size_t head = head_.load(std::memory_order_relaxed);
    const std::size_t next = head + 1 == slots_.size() ? 0 : head + 1;
    return next == tail_.load(std::memory_order_acquire);
  }
  /// Consumer: false when empty.
  bool pop(T& out) noexcept {
    const std::size_t tail = tail_.load(std::memory_order_relaxed);
    if (tail == head_.load(std::memory_order_acquire)) return false;
    out = slots_[tail];
    tail_.store(tail + 1 == slots_.size() ? 0 : tail + 1, std::memory_order_release);
    return true;
  }

 private:
  std::vector<T> slots_;
  alignas(64) std::atomic<std::size_t> head_{0};
  alignas(64) std::atomic<std::size_t> tail_{0};
};

}  // namespace bemsurg::haptics
