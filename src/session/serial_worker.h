// One thread that runs jobs in the order they are posted (issue 21): what the frame writer
// (frame_writer.h) and the processing that overlaps the capture (background.h) are built on.
// The destructor runs what is still queued, then ends the thread: declare a SerialWorker after
// everything its jobs touch, so that it goes first.
#pragma once

#include <condition_variable>
#include <cstddef>
#include <deque>
#include <exception>
#include <functional>
#include <limits>
#include <mutex>
#include <thread>

namespace acq {

class SerialWorker {
 public:
  enum class OnFailure {
    kDrop,  // a job that throws is forgotten (its work is done again later and reported there)
    kStop,  // the first failure is kept, later jobs are skipped, Post() and Wait() rethrow it
  };
  explicit SerialWorker(OnFailure on_failure);
  ~SerialWorker();
  SerialWorker(const SerialWorker&) = delete;
  SerialWorker& operator=(const SerialWorker&) = delete;

  // Queues `job`, first waiting while `max_waiting` jobs are queued; returns the seconds waited.
  double Post(std::function<void()> job,
              std::size_t max_waiting = std::numeric_limits<std::size_t>::max());
  // Waits until every job posted has run.
  void Wait();
  double busy_s() const;  // the worker's time in jobs

 private:
  void Run();
  void ThrowIfFailed() const;  // with mutex_ held

  const OnFailure on_failure_;
  mutable std::mutex mutex_;
  std::condition_variable changed_;
  std::deque<std::function<void()>> queue_;
  bool working_ = false, stopping_ = false;
  std::exception_ptr failure_;
  double busy_s_ = 0;
  std::thread thread_;  // last: started once the rest is made
};

}  // namespace acq
