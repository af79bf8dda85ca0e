#!/usr/bin/env python3
"""Evaluation matrix: simulated drives (sensors x seeds x conditions) through dlo-slam, one table.

Each drive is simulated once with dlo-simulate (cached in OUT/data/) and run through dlo-slam
with --gt; the table gives, per condition and sensor, the median and worst KITTI drift of the
odometry (before loop closure), the median and worst ATE, the drives that failed (drift above
2 %) and the median ms per scan. Extra dlo-slam settings (--set section.key=value) apply to every
run, so that two configurations can be compared on the same drives.

Conditions:
  smooth        corners entered along 8 m clothoids, per-point times (the simulator's default)
  abrupt        circular corners: the yaw rate steps to ~34 deg/s and back within a firing
  notimes       smooth corners, sweeps written without per-point times (CObservationPointCloud)
  abrupt-notimes  both
  patrol        a robot's patrol at 1.5 m/s, turning on the spot at 90 deg/s (90 and 180 deg)
  patrol-notimes  the patrol without per-point times
  patrol-fast   the patrol at 0.7 m/s turning at 150 deg/s: the robot stands, then turns 15 deg
                per sweep from the next sweep on (its first turn, scans 151-162 of every seed)
  patrol-fast-notimes  the fast patrol without per-point times
  hills         the town on steep hills: grades up to 20 % (about 15 % reached on the drive),
                crests and dips every ~55 m; the car pitches and rolls with the road
  hills-notimes   the hills without per-point times
  open-road     an open road at 15 m/s: a 585 m straight through grass with kerbs, a pole every
                ~60 m and a clump of trees every ~200 m (little constrains the scans along it)
  open-road-notimes  the open road without per-point times
  large-loop    laps of a 180 x 120 m rectangle of the town's roads (dlo-simulate --large-loop):
                180 m straights through crossings with cross traffic, new buildings along them
  large-loop-notimes  the large loop without per-point times
  stop          the town's laps with hard stops: 6 s in and every 12 s after, braking at 7 m/s^2
                to a standstill, 2 s still, accelerating again at 2.5 m/s^2
  stop-notimes  the stops without per-point times
  notimes-ccw   without per-point times, the head turning counter-clockwise (--spin ccw)
  notimes-start90  without per-point times, each sweep starting at 90 deg (left, --sweep-start 90)

Sensors (--sensors, passed to dlo-simulate --sensor): HDL64, HDL32, VLP16, OS64 and OS128
(Ouster-like, 64 and 128 beams over +22.5..-22.5 deg, 1024 columns).

Peers: --peer NAME=COMMAND (repeatable) runs an external odometry program on the same drives.
Each drive is written once as a KITTI folder (dlo-rawlog2kitti, cached in OUT/data/NAME/kitti,
with the ground truth as its poses.txt), COMMAND runs through /bin/sh with {kitti} replaced by
that folder and {out} by the poses file it must write (KITTI: one 3x4 row per scan; or TUM), and
dlo-eval evaluates the poses with the metrics dlo-slam's report uses (KITTI drift, SE(3) Umeyama
ATE, poses matched within 5 ms). The table then has a method column and the peer's rows beside
dlo-slam's; a peer's ms/scan is the wall time of its whole process / scans (file reading and
start-up included), and a peer that fails counts as a failed drive. A peer such as KISS-ICP is
built by the user from its own source; nothing of it is part of this project. --kiss-icp adds
KISS-ICP through BUILD's dlo-kiss-icp, built when BUILD was configured with its source
(-DDLO_KISS_ICP_SOURCE=...; scripts/build_kiss_icp_peer.sh).

Example:
  python3 scripts/eval_matrix.py --out /tmp/matrix --sensors HDL64 VLP16 --seeds 1 2 3
  python3 scripts/eval_matrix.py --out /tmp/matrix --peer "KISS-ICP=/path/to/driver {kitti} {out}"
  python3 scripts/eval_matrix.py --out /tmp/matrix --kiss-icp
"""
import argparse
import json
import math
import os
import re
import shlex
import statistics
import subprocess
import sys
import time

# dlo-simulate options of each condition, and the dlo-slam settings that describe its data (a
# sweep without per-point times is stamped at its first firing, as MRPT's Velodyne scans are;
# dlo-slam's default, 0.5, is KITTI's mid-sweep stamp).
CONDITIONS = {
    "smooth": ([], []),
    "abrupt": (["--corner-transition", "0"], []),
    "notimes": (["--no-point-times"], ["odometry.sweep_stamp=0"]),
    "abrupt-notimes": (["--corner-transition", "0", "--no-point-times"],
                       ["odometry.sweep_stamp=0"]),
    "patrol": (["--patrol"], []),
    "patrol-notimes": (["--patrol", "--no-point-times"], ["odometry.sweep_stamp=0"]),
    "patrol-fast": (["--patrol", "--speed", "0.7", "--turn-rate", "150"], []),
    "patrol-fast-notimes": (["--patrol", "--speed", "0.7", "--turn-rate", "150", "--no-point-times"],
                            ["odometry.sweep_stamp=0"]),
    "hills": (["--hills", "0.2"], []),
    "hills-notimes": (["--hills", "0.2", "--no-point-times"], ["odometry.sweep_stamp=0"]),
    "open-road": (["--open-road"], []),
    "open-road-notimes": (["--open-road", "--no-point-times"], ["odometry.sweep_stamp=0"]),
    "large-loop": (["--large-loop"], []),
    "large-loop-notimes": (["--large-loop", "--no-point-times"], ["odometry.sweep_stamp=0"]),
    "stop": (["--stops"], []),
    "stop-notimes": (["--stops", "--no-point-times"], ["odometry.sweep_stamp=0"]),
    # Other spin directions and sweep starts, described to dlo-slam as the data has them (its
    # firing order shows them too; the settings are the fallback for clouds without order).
    "notimes-ccw": (["--no-point-times", "--spin", "ccw"],
                    ["odometry.sweep_stamp=0", "odometry.sweep_direction=1",
                     "odometry.sweep_start_azimuth=0"]),
    "notimes-start90": (["--no-point-times", "--sweep-start", "90"],
                        ["odometry.sweep_stamp=0", "odometry.sweep_start_azimuth=90"]),
}


def run(cmd, log):
    with open(log, "w") as f:
        r = subprocess.run(cmd, stdout=f, stderr=subprocess.STDOUT)
    if r.returncode != 0:
        sys.exit(f"eval_matrix: '{' '.join(cmd)}' failed with exit {r.returncode}; see {log}")


def parse_peer(text):
    """NAME=COMMAND of --peer, checked as dlo-bench checks it."""
    name, sep, command = text.partition("=")
    if not sep or not name or not command:
        raise argparse.ArgumentTypeError(f"--peer expects NAME=COMMAND, got '{text}'")
    if not re.fullmatch(r"[A-Za-z0-9._+-]+", name):
        raise argparse.ArgumentTypeError(
            f"--peer name '{name}' may hold only letters, digits and . _ + - (it names files)")
    if "{out}" not in command:
        raise argparse.ArgumentTypeError(
            f"--peer {name}: COMMAND must contain {{out}}, the poses file it writes")
    return name, command


def kitti_folder(rawlog2kitti, data):
    """The drive in data/ as a KITTI folder with its ground truth (written once, then cached)."""
    kitti = os.path.join(data, "kitti")
    if not os.path.exists(os.path.join(kitti, "times.txt")):
        run([rawlog2kitti, os.path.join(data, "sequence.rawlog"), kitti, "--gt",
             os.path.join(data, "groundtruth.tum"), "--quiet"],
            os.path.join(data, "rawlog2kitti.log"))
    return kitti


def count_poses(path):
    with open(path) as f:
        return sum(1 for line in f if line.strip() and not line.lstrip().startswith("#"))


def run_peer(peer, kitti, res, evaluate):
    """Runs one peer on one drive's KITTI folder and evaluates its poses with dlo-eval.

    Returns a row like dlo-slam's (drift, deg100, ate, ms), or one with "error" set."""
    name, command = peer
    folder = os.path.join(res, "peer-" + name)
    os.makedirs(folder, exist_ok=True)
    poses = os.path.join(folder, "poses.txt")
    if os.path.exists(poses):
        os.remove(poses)
    line = command.replace("{kitti}", shlex.quote(kitti)).replace("{out}", shlex.quote(poses))
    scans = count_poses(os.path.join(kitti, "times.txt"))
    start = time.monotonic()
    with open(os.path.join(folder, "peer.log"), "w") as log:
        code = subprocess.run(line, shell=True, stdout=log, stderr=subprocess.STDOUT).returncode
    wall = time.monotonic() - start
    row = {"ms": 1000.0 * wall / scans, "drift": math.nan, "deg100": math.nan, "ate": math.nan}
    if code != 0:
        row["error"] = f"exited with status {code} (see {folder}/peer.log)"
    elif not os.path.exists(poses):
        row["error"] = f"wrote no poses to {poses}"
    elif count_poses(poses) != scans:
        row["error"] = f"wrote {count_poses(poses)} poses to {poses} for {scans} scans"
    else:
        ev = os.path.join(folder, "eval")
        r = subprocess.run([evaluate, "--gt", os.path.join(kitti, "poses.txt"), "--gt-times",
                            os.path.join(kitti, "times.txt"), "--est", poses, "--label", name,
                            "--max-dt", "0.005", "--out", ev],
                           stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        if r.returncode != 0:
            row["error"] = f"its poses cannot be evaluated: {r.stderr.strip()}"
        else:
            with open(os.path.join(ev, "metrics.json")) as f:
                est = json.load(f)["estimates"][0]
            row.update(drift=est["kitti"]["translation_percent"],
                       deg100=est["kitti"]["rotation_deg_per_100m"], ate=est["ate"]["rmse"])
    if "error" in row:
        print(f"eval_matrix: peer {name} failed on {res}: {row['error']}.", file=sys.stderr)
    return row


def table_row(label, rs, fail_drift):
    """One table line (condition, sensor[, method] already in `label`) for the drives `rs`;
    drives without a drift (a failed peer) count as failed and are left out of the figures."""
    ok = [r for r in rs if not math.isnan(r["drift"])]
    failed = sum(math.isnan(r["drift"]) or r["drift"] > fail_drift for r in rs)
    ran = [r for r in rs if "error" not in r]  # a peer that failed has no meaningful time

    def med(key, rows=ok):
        vals = [r[key] for r in rows if key in r]
        return f"{statistics.median(vals):.2f}" if vals else "n/a"

    def worst(key):
        return f"{max(r[key] for r in ok):.2f}" if ok else "n/a"

    return (f"| {label} | {med('drift')} | {worst('drift')} | {med('deg100')} | {med('ate')} | "
            f"{worst('ate')} | {failed} of {len(rs)} | {med('ms', ran)} | {med('p95')} |")


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", required=True, help="output folder (drives are cached in OUT/data)")
    ap.add_argument("--build", default="build", help="build folder with the apps (default build)")
    ap.add_argument("--sensors", nargs="+", default=["HDL64", "HDL32", "VLP16"],
                    help="dlo-simulate sensors: HDL64 HDL32 VLP16 OS64 OS128 "
                         "(default HDL64 HDL32 VLP16)")
    ap.add_argument("--seeds", nargs="+", type=int, default=[1, 2, 3])
    ap.add_argument("--conditions", nargs="+", default=list(CONDITIONS), choices=list(CONDITIONS))
    ap.add_argument("--frames", type=int, default=300, help="sweeps per drive (default 300)")
    ap.add_argument("--set", action="append", default=[], metavar="section.key=value",
                    help="dlo-slam override for every run (repeatable)")
    ap.add_argument("--no-condition-settings", action="store_true",
                    help="leave out the dlo-slam settings that describe each condition's data "
                         "(to run a dlo-slam that does not know them)")
    ap.add_argument("--tag", default="run", help="name of this configuration's result folder")
    ap.add_argument("--fail-drift", type=float, default=2.0,
                    help="drift (%%) above which a drive counts as failed (default 2)")
    ap.add_argument("--peer", action="append", default=[], type=parse_peer,
                    metavar="NAME=COMMAND",
                    help="external odometry run on every drive's KITTI folder; COMMAND's {kitti} "
                         "and {out} are replaced by the folder and the poses file it writes "
                         "(repeatable; see above)")
    ap.add_argument("--kiss-icp", action="store_true",
                    help="KISS-ICP as a peer, through BUILD's dlo-kiss-icp (see above)")
    a = ap.parse_args()
    if a.kiss_icp:
        driver = os.path.abspath(os.path.join(a.build, "apps/dlo-kiss-icp/dlo-kiss-icp"))
        if not os.access(driver, os.X_OK):
            ap.error(f"--kiss-icp: {driver} not found; configure the build with "
                     "-DDLO_KISS_ICP_SOURCE=... (scripts/build_kiss_icp_peer.sh)")
        a.peer.append(("KISS-ICP", f"'{driver}' --quiet {{kitti}} {{out}}"))
    if len({name for name, _ in a.peer}) != len(a.peer) or "dlo-slam" in {n for n, _ in a.peer}:
        ap.error("--peer names must differ from each other and from 'dlo-slam'")

    simulate = os.path.join(a.build, "apps/dlo-simulate/dlo-simulate")
    slam = os.path.join(a.build, "apps/dlo-slam/dlo-slam")
    rawlog2kitti = os.path.join(a.build, "apps/dlo-rawlog2kitti/dlo-rawlog2kitti")
    evaluate = os.path.join(a.build, "apps/dlo-eval/dlo-eval")
    for exe in (slam,) + ((rawlog2kitti, evaluate) if a.peer else ()):
        if not os.access(exe, os.X_OK):
            sys.exit(f"eval_matrix: {exe} not found; build first (bash scripts/build.sh)")

    rows = {}
    peer_rows = {}
    total = len(a.sensors) * len(a.seeds) * len(a.conditions)
    done = 0
    start = time.time()
    for cond in a.conditions:
        for sensor in a.sensors:
            for seed in a.seeds:
                name = f"{cond}-{sensor}-s{seed}-f{a.frames}"
                data = os.path.join(a.out, "data", name)
                if not os.path.exists(os.path.join(data, "groundtruth.tum")):
                    if not os.access(simulate, os.X_OK):
                        sys.exit(f"eval_matrix: {simulate} not found; build first")
                    os.makedirs(data, exist_ok=True)
                    run([simulate, "--out", data, "--frames", str(a.frames), "--sensor", sensor,
                         "--seed", str(seed), "--quiet"] + CONDITIONS[cond][0],
                        os.path.join(data, "simulate.log"))
                res = os.path.join(a.out, a.tag, name)
                os.makedirs(res, exist_ok=True)
                cmd = [slam, "--input", os.path.join(data, "sequence.rawlog"), "--gt",
                       os.path.join(data, "groundtruth.tum"), "--out", res, "--quiet"]
                described = [] if a.no_condition_settings else CONDITIONS[cond][1]
                for s in described + a.set:
                    cmd += ["--set", s]
                run(cmd, os.path.join(res, "slam.log"))
                with open(os.path.join(res, "report.json")) as f:
                    rep = json.load(f)
                acc = rep["accuracy"]["before_loop_closure"]
                rows.setdefault((cond, sensor), []).append({
                    "seed": seed,
                    "drift": acc["drift_percent"],
                    "deg100": acc["drift_deg_per_100m"],
                    "ate": acc["ate_rmse_m"],
                    "ate_after": rep["accuracy"]["after_loop_closure"]["ate_rmse_m"],
                    "ms": rep["ms_per_frame"]["median"],
                    "p95": rep["ms_per_frame"]["p95"],
                })
                done += 1
                r = rows[(cond, sensor)][-1]
                print(f"eval_matrix: {done}/{total} {name}: drift {r['drift']:.2f} %, "
                      f"ATE {r['ate']:.2f} m, {r['ms']:.2f} ms/scan "
                      f"({time.time() - start:.0f} s)", file=sys.stderr)
                for peer in a.peer:
                    p = run_peer(peer, kitti_folder(rawlog2kitti, data), res, evaluate)
                    p["seed"] = seed
                    peer_rows.setdefault((cond, sensor, peer[0]), []).append(p)
                    print(f"eval_matrix: {peer[0]} on {name}: drift {p['drift']:.2f} %, "
                          f"ATE {p['ate']:.2f} m, {p['ms']:.2f} ms/scan", file=sys.stderr)

    method = " method |" if a.peer else ""
    lines = [
        f"Configuration '{a.tag}' ({' '.join(a.set) or 'defaults'}), {a.frames} sweeps per drive, "
        f"seeds {' '.join(map(str, a.seeds))}; drift: KITTI metric of the odometry (before loop "
        f"closure); failed: drift above {a.fail_drift} %.",
        "",
        f"| condition | sensor |{method} drift median % | drift worst % | deg/100 m median | "
        "ATE median m | ATE worst m | failed | ms/scan median | p95 median |",
        "|---|---|" + ("---|" if a.peer else "") + "---|---|---|---|---|---|---|---|",
    ]
    for (cond, sensor), rs in rows.items():
        lines.append(table_row(f"{cond} | {sensor}" + (" | dlo-slam" if a.peer else ""), rs,
                               a.fail_drift))
        for name, _ in a.peer:
            lines.append(table_row(f"{cond} | {sensor} | {name}",
                                   peer_rows[(cond, sensor, name)], a.fail_drift))
    if a.peer:
        lines.append("")
        lines.append("Peers (external programs, run through /bin/sh on each drive's KITTI folder; "
                     "ms/scan: wall time of the whole process / scans, including its start-up "
                     "and file reading; a failed run counts as a failed drive):")
        for name, command in a.peer:
            lines.append(f"* {name}: `{command}`")
    table = "\n".join(lines) + "\n"
    with open(os.path.join(a.out, a.tag, "table.md"), "w") as f:
        f.write(table)
    with open(os.path.join(a.out, a.tag, "results.json"), "w") as f:
        results = {f"{c}/{s}": rs for (c, s), rs in rows.items()}
        results.update({f"{c}/{s}/{n}": rs for (c, s, n), rs in peer_rows.items()})
        json.dump(results, f, indent=1)
    print(table)


if __name__ == "__main__":
    main()
