#include "calib/corners.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/error.h"

namespace acq::calib {

int BoardObservation::DetectedCorners() const {
  int n = 0;
  for (const Eigen::Vector3d& c : corners) n += c.z() > 0;
  return n;
}

void WriteCornersCache(const std::string& path, const std::vector<BoardObservation>& images) {
  const std::string partial = path + ".partial";
  {
    std::ofstream out(partial);
    if (!out) throw UserError(path, "cannot write the corners cache", "check the folder exists");
    out << "# filename x y level\n";
    char line[512];
    for (const BoardObservation& obs : images) {
      if (obs.image.find_first_of(" \t\n") != std::string::npos)
        throw UserError(obs.image, "image names in a corners cache cannot contain whitespace",
                        "rename the image");
      if (!obs.found()) {
        out << obs.image << " - - -\n";
        continue;
      }
      for (const Eigen::Vector3d& c : obs.corners) {
        if (c.z() <= 0) {
          out << obs.image << " - - -\n";
          continue;
        }
        const int level = static_cast<int>(std::lround(-std::log2(c.z())));
        std::snprintf(line, sizeof line, "%s %.4f %.4f %d\n", obs.image.c_str(), c.x(), c.y(),
                      level);
        out << line;
      }
    }
    if (!out) throw UserError(path, "write failed", "check free disk space");
  }
  std::filesystem::rename(partial, path);
}

std::vector<BoardObservation> ReadCornersCache(const std::string& path, const BoardSpec& board) {
  std::ifstream in(path);
  if (!in) throw UserError(path, "cannot open the corners cache", "check the path");
  std::vector<BoardObservation> out;
  std::string line;
  int line_no = 0;
  auto finish = [&](int at_line) {
    if (out.empty()) return;
    BoardObservation& last = out.back();
    const int n = static_cast<int>(last.corners.size());
    // A single "- - -" row means "no board"; otherwise exactly the board's corner count.
    if (n == 1 && last.corners[0].z() < 0) {
      last.corners.clear();
    } else if (n != board.Corners()) {
      throw UserError(path + ":" + std::to_string(at_line),
                      "image '" + last.image + "' has " + std::to_string(n) +
                          " corner rows but the board has " + std::to_string(board.Corners()) +
                          " (" + std::to_string(board.width_n) + "x" +
                          std::to_string(board.height_n) + ")",
                      "give the --board the cache was made with");
    }
  };
  while (std::getline(in, line)) {
    ++line_no;
    const std::size_t first = line.find_first_not_of(" \t");
    if (first == std::string::npos || line[first] == '#') continue;
    std::istringstream fields(line);
    std::string name, xs, ys, ls;
    fields >> name >> xs >> ys;
    if (ys.empty())
      throw UserError(path + ":" + std::to_string(line_no),
                      "expected 'filename x y [level]', got '" + line + "'");
    fields >> ls;
    if (out.empty() || out.back().image != name) {
      finish(line_no - 1);
      out.push_back({name, {}});
    }
    Eigen::Vector3d c(-1, -1, -1);
    if (xs != "-" && ys != "-" && ls != "-") {
      try {
        c.x() = std::stod(xs);
        c.y() = std::stod(ys);
        c.z() = ls.empty() ? 1.0 : std::ldexp(1.0, -std::stoi(ls));
      } catch (const std::exception&) {
        throw UserError(path + ":" + std::to_string(line_no),
                        "x, y and level must be numbers or '-', got '" + line + "'");
      }
      if (c.x() < 0 || c.y() < 0) c = Eigen::Vector3d(-1, -1, -1);
    }
    out.back().corners.push_back(c);
  }
  finish(line_no);
  return out;
}

std::vector<bool> CoveredCells(int width, int height, const std::vector<BoardObservation>& images,
                               int nx, int ny) {
  std::vector<bool> covered(nx * ny, false);
  for (const BoardObservation& obs : images)
    for (const Eigen::Vector3d& c : obs.corners)
      if (c.z() > 0) {
        const int i = std::clamp(static_cast<int>(c.x() * nx / width), 0, nx - 1);
        const int j = std::clamp(static_cast<int>(c.y() * ny / height), 0, ny - 1);
        covered[j * nx + i] = true;
      }
  return covered;
}

std::vector<std::vector<int>> BoardSymmetries(const BoardSpec& board) {
  const int w = board.width_n, h = board.height_n;
  std::vector<std::vector<int>> out;
  std::vector<int> identity(w * h), half_turn(w * h);
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) {
      identity[j * w + i] = j * w + i;
      half_turn[j * w + i] = (h - 1 - j) * w + (w - 1 - i);
    }
  out.push_back(identity);
  out.push_back(half_turn);
  if (w == h) {
    std::vector<int> quarter(w * h), three_quarter(w * h);
    for (int j = 0; j < h; ++j)
      for (int i = 0; i < w; ++i) {
        quarter[j * w + i] = i * w + (w - 1 - j);
        three_quarter[j * w + i] = (h - 1 - i) * w + j;
      }
    out.push_back(quarter);
    out.push_back(three_quarter);
  }
  return out;
}

}  // namespace acq::calib
