// bemsurg/haptics/background_task.hpp: one seconds-long computation of the simulation side (a cut
// step and its table update) run on a thread of its own, so the simulation side stays alive while
// it computes: it keeps beating the loop's heartbeat, taking button events and offering models on
// the old snapshots, and polls the task without waiting (docs/haptics.md, "Long steps"). Before
// this, a cut step ran on the simulation thread and a step longer than the watchdog's
// stale_after_s faded the force to zero: a busy simulation read as a dead one (issue 26).
#pragma once

#include <atomic>
#include <chrono>
#include <exception>
#include <functional>
#include <memory>
#include <optional>
#include <thread>
#include <utility>

#include "bemsurg/error.hpp"
#include "bemsurg/haptics/background_threads.hpp"

namespace bemsurg::haptics {

/// One computation on its own (detached) thread, polled without blocking. The thread owns what it
/// computes from (the function object and its captures) through shared state, so a caller that
/// gives up on a hung task (an error leaves the session) never waits for it.
/// \ingroup haptics
template <class Result>
class BackgroundTask {
 public:
  /// Starts `work` on a new thread that first calls enter_background_thread(threads).
  /// Throws InvalidArgumentError while an earlier task is still running.
  void start(std::function<Result()> work, int threads) {
    if (running()) throw InvalidArgumentError("BackgroundTask: a task is already running");
    state_ = std::make_shared<State>();
    started_ = std::chrono::steady_clock::now();
    std::thread([state = state_, work = std::move(work), threads] {
      enter_background_thread(threads);
      try {
        state->result.emplace(work());
      } catch (...) { state->error = std::current_exception(); }
      state->done.store(true, std::memory_order_release);
    }).detach();
  }
  /// A task was started and its result not yet taken.
  bool busy() const noexcept { return state_ != nullptr; }
  /// Started and not finished.
  bool running() const noexcept { return state_ && !state_->done.load(std::memory_order_acquire); }
  /// Finished, result not yet taken.
  bool ready() const noexcept { return state_ && state_->done.load(std::memory_order_acquire); }
  /// Seconds since start (0 when idle).
  double seconds() const noexcept {
    return state_ ? std::chrono::duration<double>(std::chrono::steady_clock::now() - started_).count() : 0.0;
  }
  /// The result of a ready task (the task's exception is rethrown here); the task is then idle.
  Result take() {
    if (!ready()) throw InvalidArgumentError("BackgroundTask: no finished task to take");
    std::shared_ptr<State> s = std::move(state_);
    if (s->error) std::rethrow_exception(s->error);
    return std::move(*s->result);
  }

 private:
  struct State {
    std::atomic<bool> done{false};
    std::optional<Result> result;
    std::exception_ptr error;
  };
  std::shared_ptr<State> state_;
  std::chrono::steady_clock::time_point started_{};
};

}  // namespace bemsurg::haptics
