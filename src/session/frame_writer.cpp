#include "session/frame_writer.h"

#include <filesystem>

#include "core/seconds_since.h"
#include "hw/frame_file.h"

namespace acq {

FrameWriter::FrameWriter(SessionCatalog& catalog, std::size_t max_queued)
    : catalog_(catalog), max_queued_(max_queued), thread_([this] { Run(); }) {}

FrameWriter::~FrameWriter() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
  }
  changed_.notify_all();
  thread_.join();
}

void FrameWriter::Run() {
  std::unique_lock<std::mutex> lock(mutex_);
  for (;;) {
    changed_.wait(lock, [&] { return stopping_ || !queue_.empty(); });
    if (queue_.empty()) return;  // stopping, all written
    std::function<void()> job = std::move(queue_.front());
    queue_.pop_front();
    working_ = true;
    const bool failed = bool(failure_);
    lock.unlock();
    const auto start = SteadyClock::now();
    std::exception_ptr error;
    if (!failed) {  // after a failure nothing more is written: the session is ending
      try {
        job();
      } catch (...) {
        error = std::current_exception();
      }
    }
    const double spent = SecondsSince(start);
    lock.lock();
    if (error && !failure_) failure_ = error;
    busy_s_ += spent;
    working_ = false;
    changed_.notify_all();
  }
}

void FrameWriter::ThrowIfFailed() {
  if (failure_) std::rethrow_exception(failure_);
}

void FrameWriter::Write(Frame frame, std::map<std::string, std::string> attributes,
                        CatalogFrame row) {
  std::unique_lock<std::mutex> lock(mutex_);
  const auto start = SteadyClock::now();
  changed_.wait(lock, [&] { return frames_queued_ < max_queued_ || failure_; });
  blocked_s_ += SecondsSince(start);
  ThrowIfFailed();
  ++frames_queued_;
  queue_.push_back(
      [this, frame = std::move(frame), attributes = std::move(attributes), row = std::move(row)] {
        WriteFrameExr((std::filesystem::path(catalog_.directory()) / row.path).string(), frame,
                      attributes);
        catalog_.RecordFrame(row);
        std::lock_guard<std::mutex> done(mutex_);
        --frames_queued_;
      });
  changed_.notify_all();
}

void FrameWriter::After(std::function<void()> marker) {
  std::lock_guard<std::mutex> lock(mutex_);
  ThrowIfFailed();
  queue_.push_back(std::move(marker));
  changed_.notify_all();
}

void FrameWriter::Flush() {
  std::unique_lock<std::mutex> lock(mutex_);
  changed_.wait(lock, [&] { return (queue_.empty() && !working_) || failure_; });
  ThrowIfFailed();
}

double FrameWriter::busy_s() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return busy_s_;
}

double FrameWriter::blocked_s() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return blocked_s_;
}

}  // namespace acq
