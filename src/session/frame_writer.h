// Frames written into the session off the capture's thread (issue 21): a full-size frame takes
// a few tenths of a second to compress, checksum and record, time the gantry can spend moving to
// the next pose. One writer thread takes the frames in the order they were grabbed and, for
// each, keeps the catalog's rule (io/session_catalog.h): the file is written under a temporary
// name and renamed into place, then its row committed. A frame still queued when the process
// dies has no row and no file and is taken again by the resumed run, exactly as a frame whose
// grab was cut short. Markers queued between the frames run on the writer once every frame
// before them is recorded (a pose's frames all in: its merge can start).
//
// A failure to write (disk full, the session's folder gone) stops the capture: the writer
// keeps the first error and the capture's thread rethrows it at its next call.
#pragma once

#include <cstddef>
#include <functional>
#include <map>
#include <string>

#include "hw/camera.h"
#include "io/session_catalog.h"
#include "session/serial_worker.h"

namespace acq {

class FrameWriter {
 public:
  // At most `max_queued` frames and markers wait (the grab blocks beyond: memory stays bounded).
  explicit FrameWriter(SessionCatalog& catalog, std::size_t max_queued = 8);
  ~FrameWriter() = default;  // writes and records what is queued, then ends the thread

  // Queues `frame` for `row.path` (relative to the session) with its metadata; rethrows an
  // earlier write's failure.
  void Write(Frame frame, std::map<std::string, std::string> attributes, CatalogFrame row);
  // Runs `marker` on the writer once every frame queued before it is recorded.
  void After(std::function<void()> marker);
  // Waits until everything queued is written, recorded and run; rethrows a failure.
  void Flush();
  double busy_s() const { return worker_.busy_s(); }  // the writer's time spent
  double blocked_s() const { return blocked_s_; }  // the capture's, waiting for room in the queue

 private:
  SessionCatalog& catalog_;
  const std::size_t max_queued_;
  double blocked_s_ = 0;                                 // the capture's thread only
  SerialWorker worker_{SerialWorker::OnFailure::kStop};  // last: goes first
};

}  // namespace acq
