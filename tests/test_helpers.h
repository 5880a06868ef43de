// Shared helpers for the unit tests: temporary folders and the shipped data.
#pragma once

#include <filesystem>
#include <random>
#include <string>

#ifndef ACQ_DATA_DIR
#error "ACQ_DATA_DIR must point at the project's data/ folder"
#endif

namespace acq::test {

inline std::string DataPath(const std::string& relative) {
  return std::string(ACQ_DATA_DIR) + "/" + relative;
}

inline std::string Fixture(const std::string& name) {
  return std::string(ACQ_DATA_DIR) + "/../tests/data/" + name;
}

// A fresh folder under the system temp dir, removed when the object goes away.
class TempDir {
 public:
  TempDir() {
    std::random_device rd;
    path_ = std::filesystem::temp_directory_path() / ("acq-test-" + std::to_string(rd()));
    std::filesystem::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  std::string operator/(const std::string& name) const { return (path_ / name).string(); }

 private:
  std::filesystem::path path_;
};

}  // namespace acq::test
