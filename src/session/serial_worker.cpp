#include "session/serial_worker.h"

#include "core/seconds_since.h"

namespace acq {

SerialWorker::SerialWorker(OnFailure on_failure)
    : on_failure_(on_failure), thread_([this] { Run(); }) {}

SerialWorker::~SerialWorker() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
  }
  changed_.notify_all();
  thread_.join();
}

void SerialWorker::Run() {
  std::unique_lock<std::mutex> lock(mutex_);
  for (;;) {
    changed_.wait(lock, [&] { return stopping_ || !queue_.empty(); });
    if (queue_.empty()) return;  // stopping, all run
    std::function<void()> job = std::move(queue_.front());
    queue_.pop_front();
    working_ = true;
    const bool skip = bool(failure_);  // kStop after a failure: the session is ending
    lock.unlock();
    const auto start = SteadyClock::now();
    std::exception_ptr error;
    if (!skip) {
      try {
        job();
      } catch (...) {
        error = std::current_exception();
      }
    }
    const double spent = SecondsSince(start);
    lock.lock();
    if (error && on_failure_ == OnFailure::kStop && !failure_) failure_ = error;
    busy_s_ += spent;
    working_ = false;
    changed_.notify_all();
  }
}

void SerialWorker::ThrowIfFailed() const {
  if (failure_) std::rethrow_exception(failure_);
}

double SerialWorker::Post(std::function<void()> job, std::size_t max_waiting) {
  std::unique_lock<std::mutex> lock(mutex_);
  const auto start = SteadyClock::now();
  changed_.wait(lock, [&] { return queue_.size() < max_waiting || failure_; });
  const double waited = SecondsSince(start);
  ThrowIfFailed();
  queue_.push_back(std::move(job));
  changed_.notify_all();
  return waited;
}

void SerialWorker::Wait() {
  std::unique_lock<std::mutex> lock(mutex_);
  changed_.wait(lock, [&] { return (queue_.empty() && !working_) || failure_; });
  ThrowIfFailed();
}

double SerialWorker::busy_s() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return busy_s_;
}

}  // namespace acq
