#include "session/frame_writer.h"

#include <filesystem>

#include "hw/frame_file.h"

namespace acq {

FrameWriter::FrameWriter(SessionCatalog& catalog, std::size_t max_queued)
    : catalog_(catalog), max_queued_(max_queued) {}

void FrameWriter::Write(Frame frame, std::map<std::string, std::string> attributes,
                        CatalogFrame row) {
  blocked_s_ += worker_.Post(
      [this, frame = std::move(frame), attributes = std::move(attributes), row = std::move(row)] {
        WriteFrameExr((std::filesystem::path(catalog_.directory()) / row.path).string(), frame,
                      attributes);
        catalog_.RecordFrame(row);
      },
      max_queued_);
}

void FrameWriter::After(std::function<void()> marker) {
  worker_.Post(std::move(marker));
}

void FrameWriter::Flush() {
  worker_.Wait();
}

}  // namespace acq
