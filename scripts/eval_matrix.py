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
  hills         the town on steep hills: grades up to 20 % (about 15 % reached on the drive),
                crests and dips every ~55 m; the car pitches and rolls with the road
  hills-notimes   the hills without per-point times
  open-road     an open road at 15 m/s: a 585 m straight through grass with kerbs, a pole every
                ~60 m and a clump of trees every ~200 m (little constrains the scans along it)
  open-road-notimes  the open road without per-point times
  stop          the town's laps with hard stops: 6 s in and every 12 s after, braking at 7 m/s^2
                to a standstill, 2 s still, accelerating again at 2.5 m/s^2
  stop-notimes  the stops without per-point times

Example:
  python3 scripts/eval_matrix.py --out /tmp/matrix --sensors HDL64 VLP16 --seeds 1 2 3
"""
import argparse
import json
import os
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
    "hills": (["--hills", "0.2"], []),
    "hills-notimes": (["--hills", "0.2", "--no-point-times"], ["odometry.sweep_stamp=0"]),
    "open-road": (["--open-road"], []),
    "open-road-notimes": (["--open-road", "--no-point-times"], ["odometry.sweep_stamp=0"]),
    "stop": (["--stops"], []),
    "stop-notimes": (["--stops", "--no-point-times"], ["odometry.sweep_stamp=0"]),
}


def run(cmd, log):
    with open(log, "w") as f:
        r = subprocess.run(cmd, stdout=f, stderr=subprocess.STDOUT)
    if r.returncode != 0:
        sys.exit(f"eval_matrix: '{' '.join(cmd)}' failed with exit {r.returncode}; see {log}")


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", required=True, help="output folder (drives are cached in OUT/data)")
    ap.add_argument("--build", default="build", help="build folder with the apps (default build)")
    ap.add_argument("--sensors", nargs="+", default=["HDL64", "HDL32", "VLP16"])
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
    a = ap.parse_args()

    simulate = os.path.join(a.build, "apps/dlo-simulate/dlo-simulate")
    slam = os.path.join(a.build, "apps/dlo-slam/dlo-slam")
    for exe in (slam,):
        if not os.access(exe, os.X_OK):
            sys.exit(f"eval_matrix: {exe} not found; build first (bash scripts/build.sh)")

    rows = {}
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

    lines = [
        f"Configuration '{a.tag}' ({' '.join(a.set) or 'defaults'}), {a.frames} sweeps per drive, "
        f"seeds {' '.join(map(str, a.seeds))}; drift: KITTI metric of the odometry (before loop "
        f"closure); failed: drift above {a.fail_drift} %.",
        "",
        "| condition | sensor | drift median % | drift worst % | deg/100 m median | "
        "ATE median m | ATE worst m | failed | ms/scan median | p95 median |",
        "|---|---|---|---|---|---|---|---|---|---|",
    ]
    for (cond, sensor), rs in rows.items():
        d = [r["drift"] for r in rs]
        lines.append(
            f"| {cond} | {sensor} | {statistics.median(d):.2f} | {max(d):.2f} | "
            f"{statistics.median(r['deg100'] for r in rs):.2f} | "
            f"{statistics.median(r['ate'] for r in rs):.2f} | {max(r['ate'] for r in rs):.2f} | "
            f"{sum(x > a.fail_drift for x in d)} of {len(d)} | "
            f"{statistics.median(r['ms'] for r in rs):.2f} | "
            f"{statistics.median(r['p95'] for r in rs):.2f} |")
    table = "\n".join(lines) + "\n"
    with open(os.path.join(a.out, a.tag, "table.md"), "w") as f:
        f.write(table)
    with open(os.path.join(a.out, a.tag, "results.json"), "w") as f:
        json.dump({f"{c}/{s}": rs for (c, s), rs in rows.items()}, f, indent=1)
    print(table)


if __name__ == "__main__":
    main()
