#include "dlo/bench/peer_run.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cctype>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <limits>
#include <stdexcept>

#include "dlo/core/stage_times.h"
#include "dlo/metrics/trajectory_io.h"

namespace dlo::bench {

namespace {

/// Single-quotes `text` for /bin/sh.
std::string shellQuote(const std::string& text) {
  std::string quoted = "'";
  for (const char c : text) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

void replaceAll(std::string& text, const std::string& from, const std::string& to) {
  for (size_t at = text.find(from); at != std::string::npos; at = text.find(from, at + to.size())) {
    text.replace(at, from.size(), to);
  }
}

/// How a child that did not exit with status 0 ended, as the end of a sentence.
std::string describeStatus(int status) {
  if (WIFSIGNALED(status)) {
    return "was killed by signal " + std::to_string(WTERMSIG(status)) + " (" +
           strsignal(WTERMSIG(status)) + ")";
  }
  return "exited with status " + std::to_string(WEXITSTATUS(status));
}

}  // namespace

PeerSpec parsePeerSpec(const std::string& text) {
  const size_t equals = text.find('=');
  if (equals == std::string::npos || equals == 0 || equals + 1 == text.size()) {
    throw std::invalid_argument("--peer expects NAME=COMMAND, got '" + text + "'.");
  }
  PeerSpec peer{text.substr(0, equals), text.substr(equals + 1)};
  for (const char c : peer.name) {
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '_' || c == '+' ||
          c == '-')) {
      throw std::invalid_argument("--peer name '" + peer.name +
                                  "' may hold only letters, digits and . _ + - (it names files).");
    }
  }
  if (peer.command.find("{out}") == std::string::npos) {
    throw std::invalid_argument("--peer " + peer.name +
                                ": COMMAND must contain {out}, the poses file it writes.");
  }
  return peer;
}

std::string peerCommandLine(const std::string& command, const std::string& kitti_dir,
                            const std::string& out_poses) {
  std::string line = command;
  replaceAll(line, "{kitti}", shellQuote(kitti_dir));
  replaceAll(line, "{out}", shellQuote(out_poses));
  return line;
}

MethodRun runPeer(const PeerSpec& peer, const std::string& kitti_dir,
                  const std::vector<double>& scan_times, const std::string& out_poses,
                  const std::string& log_path) {
  MethodRun run;
  run.method = peer.name;
  std::error_code ec;
  std::filesystem::remove(out_poses, ec);  // a file left by an earlier run is not this run's
  const std::string line = peerCommandLine(peer.command, kitti_dir, out_poses);
  // The peer's peak memory is not measured: the high-water mark a child reports includes this
  // process's at the exec (Linux keeps the old mm's hiwater), which is larger than a peer's.
  posix_spawn_file_actions_t files;
  posix_spawn_file_actions_init(&files);
  posix_spawn_file_actions_addopen(&files, STDOUT_FILENO, log_path.c_str(),
                                   O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&files, STDOUT_FILENO, STDERR_FILENO);
  const char* argv[] = {"sh", "-c", line.c_str(), nullptr};
  const Stopwatch watch;
  pid_t pid = 0;
  const int spawned =
      ::posix_spawn(&pid, "/bin/sh", &files, nullptr, const_cast<char* const*>(argv), environ);
  posix_spawn_file_actions_destroy(&files);
  if (spawned != 0) {
    run.error = "cannot start /bin/sh with its output to '" + log_path +
                "': " + std::strerror(spawned) + ".";
    return run;
  }
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  const double wall_ms = watch.elapsedMs();
  run.peak_memory_mb = std::numeric_limits<double>::quiet_NaN();
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    run.error = "the command " + describeStatus(status) + " (its output is in '" + log_path + "').";
    return run;
  }
  if (!std::filesystem::exists(out_poses)) {
    run.error = "the command wrote no poses to {out} ('" + out_poses + "').";
    return run;
  }
  metrics::Trajectory trajectory;
  try {
    trajectory = metrics::readTrajectory(out_poses, {});
  } catch (const std::exception& e) {
    run.error = std::string("its poses cannot be read: ") + e.what();
    return run;
  }
  if (trajectory.size() != scan_times.size()) {
    run.error = "it wrote " + std::to_string(trajectory.size()) + " poses to '" + out_poses +
                "' for " + std::to_string(scan_times.size()) + " scans; expected one per scan.";
    return run;
  }
  if (metrics::detectTrajectoryFormat(out_poses) == metrics::TrajectoryFormat::kKitti) {
    trajectory.times = scan_times;
  }
  // As the other methods' trajectories: relative to the first scan.
  const Eigen::Isometry3d first_inverse = trajectory.poses.front().inverse();
  for (Eigen::Isometry3d& pose : trajectory.poses) pose = first_inverse * pose;
  run.trajectory = std::move(trajectory);
  run.ms.assign(scan_times.size(), wall_ms / static_cast<double>(scan_times.size()));
  return run;
}

}  // namespace dlo::bench
