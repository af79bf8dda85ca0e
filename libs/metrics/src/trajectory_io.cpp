#include "dlo/metrics/trajectory_io.h"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <stdexcept>

#include "dlo/files/atomic_file.h"

namespace dlo::metrics {

namespace {

/// The numbers of one line of a text trajectory, with where it came from for error messages.
struct Line {
  int number = 0;  ///< 1-based
  std::vector<double> values;
};

std::runtime_error lineError(const std::string& path, int line, const std::string& what) {
  return std::runtime_error("'" + path + "' line " + std::to_string(line) + ": " + what + ".");
}

/// Splits a line into numbers; returns false on a token that is not a finite number.
bool parseNumbers(const std::string& text, std::vector<double>& out) {
  out.clear();
  const char* p = text.c_str();
  while (true) {
    while (*p == ' ' || *p == '\t' || *p == ',' || *p == '\r') ++p;
    if (*p == '\0') return true;
    char* end = nullptr;
    errno = 0;
    const double v = std::strtod(p, &end);
    if (end == p || errno == ERANGE || !std::isfinite(v)) return false;
    if (*end != '\0' && *end != ' ' && *end != '\t' && *end != ',' && *end != '\r') return false;
    out.push_back(v);
    p = end;
  }
}

/// Calls `visit` for each data line ('#' comments and blank lines skipped); malformed numbers
/// throw with the line number.
void forEachLine(const std::string& path, const std::function<void(const Line&)>& visit) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot open '" + path + "' for reading.");
  std::string text;
  Line line;
  while (std::getline(in, text)) {
    ++line.number;
    const size_t first = text.find_first_not_of(" \t\r");
    if (first == std::string::npos || text[first] == '#') continue;
    if (!parseNumbers(text, line.values)) {
      throw lineError(path, line.number, "expected only numbers, got \"" + text + "\"");
    }
    visit(line);
  }
}

/// Writes through dlo::writeAtomically with a stdio stream for `body`. The reasons fill the
/// OutputError's "cannot write 'path' (reason)."
void writeAtomically(const std::string& path, const std::function<void(std::FILE*)>& body) {
  dlo::writeAtomically(path, [&](const std::string& temp) {
    std::FILE* f = std::fopen(temp.c_str(), "w");
    if (!f) throw std::runtime_error("its folder is missing or not writable");
    body(f);
    const bool ok = !std::ferror(f);
    if (std::fclose(f) != 0 || !ok) throw std::runtime_error("disk full?");
  });
}

}  // namespace

TrajectoryFormat detectTrajectoryFormat(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot open '" + path + "' for reading.");
  std::string text;
  std::vector<double> values;
  for (int number = 1; std::getline(in, text); ++number) {
    const size_t first = text.find_first_not_of(" \t\r");
    if (first == std::string::npos || text[first] == '#') continue;
    if (parseNumbers(text, values) && values.size() == 8) return TrajectoryFormat::kTum;
    if (parseNumbers(text, values) && values.size() == 12) return TrajectoryFormat::kKitti;
    throw lineError(path, number,
                    "expected 8 numbers (TUM: t x y z qx qy qz qw) or 12 (KITTI: 3x4 matrix)");
  }
  throw std::runtime_error("'" + path + "' holds no pose.");
}

Trajectory readTumTrajectory(const std::string& path) {
  Trajectory out;
  forEachLine(path, [&](const Line& line) {
    const std::vector<double>& v = line.values;
    if (v.size() != 8) {
      throw lineError(path, line.number,
                      "expected 8 numbers (t x y z qx qy qz qw), got " + std::to_string(v.size()));
    }
    Eigen::Quaterniond q(v[7], v[4], v[5], v[6]);
    if (q.norm() < 1e-6) throw lineError(path, line.number, "the quaternion is zero");
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.linear() = q.normalized().toRotationMatrix();
    pose.translation() = Eigen::Vector3d(v[1], v[2], v[3]);
    out.push_back(v[0], pose);
  });
  return out;
}

Trajectory readKittiTrajectory(const std::string& path, const std::vector<double>& times) {
  Trajectory out;
  forEachLine(path, [&](const Line& line) {
    const std::vector<double>& v = line.values;
    if (v.size() != 12) {
      throw lineError(path, line.number,
                      "expected 12 numbers (row-major 3x4 [R|t]), got " + std::to_string(v.size()));
    }
    Eigen::Matrix3d R;
    R << v[0], v[1], v[2], v[4], v[5], v[6], v[8], v[9], v[10];
    // Files with 6 significant digits leave R slightly non-orthonormal; project it back.
    const Eigen::JacobiSVD<Eigen::Matrix3d> svd(R, Eigen::ComputeFullU | Eigen::ComputeFullV);
    R = svd.matrixU() * svd.matrixV().transpose();
    if (R.determinant() < 0) throw lineError(path, line.number, "the rotation is a reflection");
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.linear() = R;
    pose.translation() = Eigen::Vector3d(v[3], v[7], v[11]);
    out.push_back(static_cast<double>(out.size()), pose);
  });
  if (!times.empty()) {
    if (times.size() != out.size()) {
      throw std::runtime_error("'" + path + "' holds " + std::to_string(out.size()) +
                               " poses but " + std::to_string(times.size()) +
                               " timestamps were given.");
    }
    out.times = times;
  }
  return out;
}

Trajectory readTrajectory(const std::string& path, const std::vector<double>& kitti_times) {
  return detectTrajectoryFormat(path) == TrajectoryFormat::kTum
             ? readTumTrajectory(path)
             : readKittiTrajectory(path, kitti_times);
}

std::vector<double> readTimestamps(const std::string& path) {
  std::vector<double> out;
  forEachLine(path, [&](const Line& line) {
    if (line.values.size() != 1) {
      throw lineError(
          path, line.number,
          "expected one timestamp, got " + std::to_string(line.values.size()) + " numbers");
    }
    out.push_back(line.values[0]);
  });
  return out;
}

TumWriter::TumWriter(const std::string& path, const std::string& header) : output_(path) {
  file_ = std::fopen(output_.temp().c_str(), "w");
  if (!file_) {
    throw OutputError("cannot write '" + path + "' (its folder is missing or not writable).");
  }
  std::fputs(header.c_str(), file_);
}

TumWriter::~TumWriter() {
  if (file_) std::fclose(file_);
}

void TumWriter::write(double time, const Eigen::Isometry3d& pose) {
  std::fprintf(file_, "%.9f ", time);
  writePose(pose);
}

void TumWriter::write(std::int64_t seconds, std::int64_t nanoseconds,
                      const Eigen::Isometry3d& pose) {
  const std::int64_t ns = seconds * 1000000000 + nanoseconds;
  std::fprintf(file_, "%lld.%09lld ", static_cast<long long>(ns / 1000000000),
               static_cast<long long>(ns % 1000000000));
  writePose(pose);
}

void TumWriter::writePose(const Eigen::Isometry3d& pose) {
  const Eigen::Vector3d t = pose.translation();
  const Eigen::Quaterniond q(pose.rotation());
  std::fprintf(file_, "%.9f %.9f %.9f %.9f %.9f %.9f %.9f\n", t.x(), t.y(), t.z(), q.x(), q.y(),
               q.z(), q.w());
}

void TumWriter::commit() {
  const bool ok = !std::ferror(file_);
  const bool closed = std::fclose(file_) == 0;
  file_ = nullptr;
  if (!ok || !closed) throw OutputError("cannot write '" + output_.path() + "' (disk full?).");
  output_.commit();
}

void writeTumTrajectory(const std::string& path, const Trajectory& trajectory, TumHeader header) {
  TumWriter out(path, header == TumHeader::kColumnNames ? "# t x y z qx qy qz qw\n" : "");
  for (size_t i = 0; i < trajectory.size(); ++i)
    out.write(trajectory.times[i], trajectory.poses[i]);
  out.commit();
}

void writeKittiTrajectory(const std::string& path, const Trajectory& trajectory) {
  writeAtomically(path, [&](std::FILE* f) {
    for (const Eigen::Isometry3d& pose : trajectory.poses) {
      const Eigen::Matrix<double, 3, 4> m = pose.matrix().topRows<3>();
      for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 4; ++c) {
          std::fprintf(f, (r == 2 && c == 3) ? "%.9e\n" : "%.9e ", m(r, c));
        }
      }
    }
  });
}

void writeTimestamps(const std::string& path, const std::vector<double>& times) {
  writeAtomically(path, [&](std::FILE* f) {
    for (double t : times) std::fprintf(f, "%.9f\n", t);
  });
}

}  // namespace dlo::metrics
