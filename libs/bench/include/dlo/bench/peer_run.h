/// \file peer_run.h
/// \brief An external odometry program (a "peer", dlo-bench --peer NAME=COMMAND) run on the
/// benchmark's scans, handed to it as a KITTI folder, its poses read back as a MethodRun.
#pragma once

#include <string>
#include <vector>

#include "dlo/bench/method_run.h"

namespace dlo::bench {

/// A peer as given on the command line: `NAME=COMMAND`.
struct PeerSpec {
  std::string name;     ///< its row in the table and its files' names, e.g. "KISS-ICP"
  std::string command;  ///< a /bin/sh command with the placeholders {kitti} and {out}
};

/// Parses "NAME=COMMAND". NAME is letters, digits and ". _ + -" (it names files); COMMAND must
/// contain {out}. \throws std::invalid_argument with one sentence saying what is wrong.
PeerSpec parsePeerSpec(const std::string& text);

/// `command` with every {kitti} and {out} replaced by the shell-quoted paths.
std::string peerCommandLine(const std::string& command, const std::string& kitti_dir,
                            const std::string& out_poses);

/// Runs `peer` once through /bin/sh on the KITTI folder `kitti_dir` (as KittiFolderWriter writes
/// it; `scan_times` are its times.txt), its stdout and stderr going to `log_path`, and reads the
/// poses it wrote to `out_poses`: KITTI (one row-major 3x4 pose per scan, stamped with
/// `scan_times`) or TUM (its own stamps), detected from the first line. The whole process is
/// timed, so every scan gets the same time, wall time / scans, which includes the peer's
/// start-up and its reading of the files; its peak memory is not measured (NaN). A peer that exits
/// non-zero, dies, writes no or unreadable poses, or a number of poses other than the number of
/// scans gives a MethodRun whose error says so in one sentence (and no trajectory).
MethodRun runPeer(const PeerSpec& peer, const std::string& kitti_dir,
                  const std::vector<double>& scan_times, const std::string& out_poses,
                  const std::string& log_path);

}  // namespace dlo::bench
