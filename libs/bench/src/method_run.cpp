#include "dlo/bench/method_run.h"

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <csignal>
#include <cstring>
#include <sstream>
#include <stdexcept>

#include "dlo/app/progress_bar.h"
#include "dlo/core/stage_times.h"
#include "dlo/metrics/error_statistics.h"
#include "dlo/mrpt/rawlog_scan_source.h"
#include "dlo/slam/process_memory.h"

namespace dlo::bench {

namespace {

std::string firstLine(const std::string& text) {
  return text.substr(0, text.find('\n'));
}

/// A line-oriented text form of a MethodRun for the pipe: one keyword per line, full precision.
std::string serialise(const MethodRun& run) {
  std::ostringstream o;
  o.precision(17);
  o << "peak " << run.peak_memory_mb << "\nbaseline " << run.baseline_memory_mb << "\n";
  if (!run.error.empty()) o << "error " << firstLine(run.error) << "\n";
  if (!run.input_warning.empty()) o << "warning " << firstLine(run.input_warning) << "\n";
  for (size_t i = 0; i < run.trajectory.size(); ++i) {
    const Eigen::Isometry3d& T = run.trajectory.poses[i];
    const Eigen::Quaterniond q(T.rotation());
    o << "pose " << run.ms[i] << " " << run.trajectory.times[i] << " " << T.translation().x() << " "
      << T.translation().y() << " " << T.translation().z() << " " << q.x() << " " << q.y() << " "
      << q.z() << " " << q.w() << "\n";
  }
  o << "end\n";
  return o.str();
}

bool parse(const std::string& text, MethodRun& run) {
  std::istringstream in(text);
  std::string line;
  bool ended = false;
  while (std::getline(in, line)) {
    std::istringstream f(line);
    std::string key;
    f >> key;
    if (key == "peak") {
      f >> run.peak_memory_mb;
    } else if (key == "baseline") {
      f >> run.baseline_memory_mb;
    } else if (key == "error" || key == "warning") {
      std::string rest;
      std::getline(f >> std::ws, rest);
      (key == "error" ? run.error : run.input_warning) = rest;
    } else if (key == "pose") {
      double ms = 0, t = 0, x = 0, y = 0, z = 0, qx = 0, qy = 0, qz = 0, qw = 1;
      if (!(f >> ms >> t >> x >> y >> z >> qx >> qy >> qz >> qw)) return false;
      Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
      T.linear() = Eigen::Quaterniond(qw, qx, qy, qz).normalized().toRotationMatrix();
      T.translation() = Eigen::Vector3d(x, y, z);
      run.ms.push_back(ms);
      run.trajectory.push_back(t, T);
    } else if (key == "end") {
      ended = true;
    }
  }
  return ended;
}

void writeAll(int fd, const std::string& text) {
  size_t done = 0;
  while (done < text.size()) {
    const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return;
    done += static_cast<size_t>(n);
  }
}

}  // namespace

MethodRun runMethod(const MethodSpec& spec, ScanSource& source, long max_frames, bool progress) {
  MethodRun run;
  run.method = spec.name;
  run.baseline_memory_mb = residentMemoryMb();
  try {
    const std::unique_ptr<OdometryMethod> method = spec.create();
    ProgressBar bar(max_frames > 0 ? static_cast<size_t>(max_frames) : 0, "scans", progress);
    TimedScan scan;
    while ((max_frames < 0 || static_cast<long>(run.ms.size()) < max_frames) && source.next(scan)) {
      const double time = scan.timestampSeconds();
      const Stopwatch watch;
      const Eigen::Isometry3d pose = method->process(time, scan.points, scan.point_times);
      run.ms.push_back(watch.elapsedMs());
      run.trajectory.push_back(time, pose);
      bar.update(run.ms.size());
    }
    bar.finish(run.ms.size());
    method->finalise(run.trajectory);
    run.input_warning = source.stats().error;
  } catch (const std::exception& e) {
    run.error = firstLine(e.what());
  }
  if (run.trajectory.size() != run.ms.size()) {
    run.error = "the final trajectory has " + std::to_string(run.trajectory.size()) +
                " poses for " + std::to_string(run.ms.size()) + " scans.";
  }
  run.peak_memory_mb = peakResidentMemoryMb();
  return run;
}

MethodRun runMethodIsolated(const MethodSpec& spec, const std::string& rawlog,
                            const ScanSourceOptions& options, long max_frames, bool progress) {
  MethodRun failed;
  failed.method = spec.name;
  int fds[2];
  if (::pipe(fds) != 0) {
    failed.error = std::string("cannot create a pipe: ") + std::strerror(errno);
    return failed;
  }
  const pid_t pid = ::fork();
  if (pid < 0) {
    failed.error = std::string("cannot fork: ") + std::strerror(errno);
    ::close(fds[0]);
    ::close(fds[1]);
    return failed;
  }
  if (pid == 0) {
    ::close(fds[0]);
    resetPeakMemory();
    MethodRun run;
    try {
      RawlogScanSource source(rawlog, options);
      run = runMethod(spec, source, max_frames, progress);
    } catch (const std::exception& e) {
      run.error = firstLine(e.what());
    }
    writeAll(fds[1], serialise(run));
    ::close(fds[1]);
    // _exit: the parent's atexit handlers and static destructors are not the child's to run.
    ::_exit(0);
  }
  ::close(fds[1]);
  std::string text;
  char buffer[65536];
  for (;;) {
    const ssize_t n = ::read(fds[0], buffer, sizeof buffer);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    text.append(buffer, static_cast<size_t>(n));
  }
  ::close(fds[0]);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  MethodRun run;
  run.method = spec.name;
  if (!parse(text, run)) {
    failed.error = WIFSIGNALED(status) ? "the process running it died of signal " +
                                             std::to_string(WTERMSIG(status)) + " (" +
                                             strsignal(WTERMSIG(status)) + ")."
                                       : "the process running it ended without a result (status " +
                                             std::to_string(WEXITSTATUS(status)) + ").";
    return failed;
  }
  return run;
}

MethodRun combinePasses(const std::vector<MethodRun>& passes) {
  if (passes.empty()) throw std::invalid_argument("combinePasses needs at least one pass");
  const int count = static_cast<int>(passes.size());
  for (const MethodRun& pass : passes) {
    if (!pass.error.empty()) {
      MethodRun failed = pass;
      failed.passes = count;
      return failed;
    }
  }
  MethodRun combined = passes.front();
  combined.passes = count;
  size_t n = combined.ms.size();
  for (const MethodRun& pass : passes) n = std::min({n, pass.ms.size(), pass.trajectory.size()});
  combined.ms.resize(n);
  combined.trajectory.times.resize(n);
  combined.trajectory.poses.resize(n);
  std::vector<double> times(passes.size());
  for (size_t i = 0; i < n; ++i) {
    for (size_t k = 0; k < passes.size(); ++k) times[k] = passes[k].ms[i];
    combined.ms[i] = metrics::errorStatistics(times).median;
    for (const MethodRun& pass : passes) {
      const double apart =
          (pass.trajectory.poses[i].translation() - combined.trajectory.poses[i].translation())
              .norm();
      combined.pass_disagreement_m = std::max(combined.pass_disagreement_m, apart);
    }
  }
  for (const MethodRun& pass : passes) {
    combined.peak_memory_mb = std::max(combined.peak_memory_mb, pass.peak_memory_mb);
  }
  return combined;
}

}  // namespace dlo::bench
