// bemsurg/haptics/triple_buffer.hpp: lock-free single-producer / single-consumer hand-over of a
// snapshot between threads running at different rates (docs/design.md §6: the haptic path reads
// immutable snapshots; SOFA publishes its contact operator the same way).
//
// Three slots: the writer fills its back slot and publish()es it (one atomic exchange); the reader
// takes the newest published slot with acquire() (one atomic exchange) and reads it undisturbed
// until its next acquire(). Neither side ever waits or allocates; a slow reader simply skips
// snapshots. T is constructed three times up front (give it its capacity there), then only
// overwritten in place.
#pragma once

#include <atomic>
#include <cstdint>

namespace bemsurg::haptics {

/// Lock-free single-producer / single-consumer hand-over of a snapshot between threads running at different rates: the
/// writer publish()es its back slot, the reader acquire()s the newest one. Neither side waits or allocates.
/// \ingroup haptics
template <class T>
class TripleBuffer {
 public:
  TripleBuffer() = default;
  explicit TripleBuffer(const T& prototype) : slots_{prototype, prototype, prototype} {}

  // ---- writer thread ----
  /// The slot to fill; it belongs to the writer until publish().
  T& back() { return slots_[back_]; }
  /// Hands the back slot to the reader and takes the previously shared slot as the new back.
  void publish() {
    const std::uint8_t old = shared_.exchange(static_cast<std::uint8_t>(back_ | kFresh), std::memory_order_acq_rel);
    back_ = old & kIndex;
  }

  // ---- reader thread ----
  /// Switches to the newest published snapshot if there is one; returns whether it changed.
  bool acquire() {
    if (!(shared_.load(std::memory_order_relaxed) & kFresh)) return false;
    const std::uint8_t old = shared_.exchange(front_, std::memory_order_acq_rel);
    front_ = old & kIndex;
    return true;
  }
  /// The snapshot acquired last (the prototype until the first publish).
  const T& front() const { return slots_[front_]; }

 private:
  static constexpr std::uint8_t kIndex = 0x3;
  static constexpr std::uint8_t kFresh = 0x4;
  T slots_[3];
  std::uint8_t back_ = 0;
  std::uint8_t front_ = 1;
  std::atomic<std::uint8_t> shared_{2};
};

}  // namespace bemsurg::haptics
