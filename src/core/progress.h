// Progress on long work: a line on stderr when a stage starts, then at most every ~2 seconds,
// then when it ends, so a user watching a multi-minute job knows it is alive and how far along.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdio>
#include <mutex>
#include <string>

namespace acq {

class Progress {
 public:
  Progress(std::string stage, std::size_t total, bool enabled = true)
      : stage_(std::move(stage)),
        total_(total),
        enabled_(enabled),
        start_(Clock::now()),
        last_(start_) {
    if (enabled_) std::fprintf(stderr, "%s: 0/%zu\n", stage_.c_str(), total_);
  }
  ~Progress() {
    if (enabled_)
      std::fprintf(stderr, "%s: done, %zu in %.1f s\n", stage_.c_str(), done_.load(),
                   Seconds(Clock::now() - start_));
  }
  void Tick(std::size_t n = 1) {
    const std::size_t done = done_ += n;
    if (!enabled_) return;
    std::lock_guard<std::mutex> lock(mutex_);
    const auto now = Clock::now();
    if (Seconds(now - last_) < 2.0) return;
    last_ = now;
    std::fprintf(stderr, "%s: %zu/%zu (%.0f%%)\n", stage_.c_str(), done, total_,
                 100.0 * double(done) / double(total_ ? total_ : 1));
  }

 private:
  using Clock = std::chrono::steady_clock;
  static double Seconds(Clock::duration d) { return std::chrono::duration<double>(d).count(); }
  std::string stage_;
  std::size_t total_;
  bool enabled_;
  std::atomic<std::size_t> done_{0};
  std::mutex mutex_;
  Clock::time_point start_, last_;
};

}  // namespace acq
