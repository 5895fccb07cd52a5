#pragma once
/// \file
/// A task run beside the caller's own work: on a second thread when one may be used, else at
/// once, on the caller's thread (the order the stages ran in before they overlapped). Used
/// where two stages read the same finished data and neither needs the other's result (the
/// validation beside the harmonic placement; the mesh's STC beside the valence statistics).
/// Results never depend on which way it ran: only the time does.

#include <chrono>
#include <exception>
#include <optional>
#include <thread>
#include <utility>

namespace stcweave::primal {

/// Whether a run asked for `threads` threads (0: one per hardware thread, the convention of
/// `PositionOptions::threads`) may run a stage on a second thread: not with 1, nor on a
/// machine with one hardware thread.
[[nodiscard]] inline bool second_thread(int threads) {
  return threads != 1 && std::thread::hardware_concurrency() > 1;
}

/// Runs `task` (a callable returning T) on a second thread when `parallel`, else at once.
/// `get` waits for it and returns its result or rethrows its exception; `seconds` is the
/// task's own duration. Not copyable or movable (the thread writes into it); the destructor
/// waits for a task still running, so nothing outlives what it reads.
template <class T>
class Beside {
 public:
  template <class Task>
  Beside(bool parallel, Task&& task) {
    if (parallel) {
      thread_ = std::thread([this, t = std::forward<Task>(task)]() mutable { run(t); });
    } else {
      run(task);
    }
  }
  Beside(const Beside&) = delete;
  Beside& operator=(const Beside&) = delete;
  Beside(Beside&&) = delete;
  Beside& operator=(Beside&&) = delete;
  ~Beside() {
    if (thread_.joinable()) thread_.join();
  }

  /// The task's result (once: it is moved out), or its exception rethrown.
  T get() {
    if (thread_.joinable()) thread_.join();
    if (error_) std::rethrow_exception(error_);
    return std::move(*value_);
  }
  /// The task's own duration (valid after `get`).
  [[nodiscard]] double seconds() const { return seconds_; }

 private:
  template <class Task>
  void run(Task& task) {
    const auto start = std::chrono::steady_clock::now();
    try {
      value_.emplace(task());
    } catch (...) {
      error_ = std::current_exception();
    }
    seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }

  std::optional<T> value_;
  std::exception_ptr error_;
  double seconds_ = 0.0;
  std::thread thread_;
};

}  // namespace stcweave::primal
