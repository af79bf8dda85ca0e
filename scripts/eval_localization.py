#!/usr/bin/env python3
"""Localisation benchmark: dlo-localize on simulated drives through a town that dlo-slam mapped.

For each sensor and seed: dlo-simulate drives the block once (--frames scans, town --seed S) and
dlo-slam maps it; a second day in the same town (--traffic-seed S+100: other parked and moving
cars, other noise) is localised by dlo-localize from no initial pose. Drives and maps are cached in OUT/data.

Per drive the table gives the fraction of scans localised, the scan of the first fix, the
re-localisations, the position error in the map's frame (RMS and worst, planar, against where the
map puts each place: both days follow the same route on the same clock, so that is dlo-slam's pose
of the first day at the same time), the error against the world's truth (the map's own error
included) and dlo-localize's ms per scan (median, p95: the odometry that runs beside it, the
registration against the map, the searches).

Example:
  python3 scripts/eval_localization.py --out /tmp/loc --sensors HDL64 VLP16 --seeds 1 2 3
"""
import argparse
import json
import math
import os
import statistics
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from eval_matrix import run  # noqa: E402  (one command runner for both scripts)


def load_tum(path):
    rows = []
    with open(path) as f:
        for line in f:
            if line.strip() and not line.startswith("#"):
                rows.append([float(v) for v in line.split()])
    return rows


def qmul(a, b):
    ax, ay, az, aw = a
    bx, by, bz, bw = b
    return (aw * bx + ax * bw + ay * bz - az * by, aw * by - ax * bz + ay * bw + az * bx,
            aw * bz + ax * by - ay * bx + az * bw, aw * bw - ax * bx - ay * by - az * bz)


def in_frame_of(origin, row):
    """Position of TUM `row` in the frame of TUM pose `origin` (x, y)."""
    q = (-origin[4], -origin[5], -origin[6], origin[7])
    d = (row[1] - origin[1], row[2] - origin[2], row[3] - origin[3], 0.0)
    p = qmul(qmul(q, d), (origin[4], origin[5], origin[6], origin[7]))
    return p[0], p[1]


def errors(estimate, reference, to_reference=lambda r: (r[1], r[2])):
    by_time = {round(r[0], 3): r for r in reference}
    out = []
    for e in estimate:
        r = by_time.get(round(e[0], 3))
        if r is not None:
            x, y = to_reference(r)
            out.append(math.hypot(e[1] - x, e[2] - y))
    return out


def rms(v):
    return math.sqrt(sum(x * x for x in v) / len(v)) if v else float("nan")


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", required=True, help="output folder (drives cached in OUT/data)")
    ap.add_argument("--build", default="build", help="build folder with the apps (default build)")
    ap.add_argument("--sensors", nargs="+", default=["HDL64", "VLP16"])
    ap.add_argument("--seeds", nargs="+", type=int, default=[1, 2, 3])
    ap.add_argument("--frames", type=int, default=300, help="scans of the mapping drive")
    ap.add_argument("--day2-frames", type=int, default=200, help="scans of the second day")
    ap.add_argument("--patrol", action="store_true",
                    help="both days a robot's patrol (dlo-simulate --patrol: 1.5 m/s, turns on "
                         "the spot at 90 deg/s) instead of a car's lap; cached apart")
    ap.add_argument("--set", action="append", default=[], metavar="section.key=value",
                    help="passed on to dlo-localize (e.g. localizer.bridge_only=true); repeatable")
    args = ap.parse_args()
    apps = {n: os.path.join(args.build, "apps", n, n)
            for n in ("dlo-simulate", "dlo-slam", "dlo-localize")}
    for n, p in apps.items():
        if not os.access(p, os.X_OK):
            sys.exit(f"eval_localization: {p} not found: build first (or give --build)")
    rows = []
    for sensor in args.sensors:
        for seed in args.seeds:
            kind = "-patrol" if args.patrol else ""
            base = os.path.join(args.out, "data", f"{sensor}{kind}-s{seed}")
            day1, day2 = os.path.join(base, "day1"), os.path.join(base, "day2")
            mapped, loc = os.path.join(base, "map"), os.path.join(base, "localize")
            os.makedirs(base, exist_ok=True)
            for d, extra, frames in ((day1, [], args.frames),
                                     (day2, ["--traffic-seed", str(seed + 100)], args.day2_frames)):
                if not os.path.exists(os.path.join(d, "sequence.rawlog")):
                    run([apps["dlo-simulate"], "--out", d, "--frames", str(frames), "--sensor",
                         sensor, "--seed", str(seed), "--quiet"] + extra +
                        (["--patrol"] if args.patrol else []), d + ".log")
            if not os.path.exists(os.path.join(mapped, "report.json")):
                run([apps["dlo-slam"], "--input", os.path.join(day1, "sequence.rawlog"), "--gt",
                     os.path.join(day1, "groundtruth.tum"), "--out", mapped, "--quiet"],
                    mapped + ".log")
            rawlog = os.path.join(day2, "sequence.rawlog")
            run([apps["dlo-localize"], "--map", mapped, "--input", rawlog, "--out", loc,
                 "--quiet"] + [x for a in args.set for x in ("--set", a)], loc + ".log")
            report = json.load(open(os.path.join(loc, "report.json")))
            est = load_tum(os.path.join(loc, "trajectory.tum"))
            map_err = errors(est, load_tum(os.path.join(mapped, "trajectory.tum")))
            truth1 = load_tum(os.path.join(day1, "groundtruth.tum"))
            world_err = errors(est, load_tum(os.path.join(day2, "groundtruth.tum")),
                               lambda r: in_frame_of(truth1[0], r))
            slam = json.load(open(os.path.join(mapped, "report.json")))
            rows.append({
                "sensor": sensor, "seed": seed,
                "localised": report["localised_fraction"],
                "first_fix": report["first_fix"]["scan"] if report["first_fix"] else None,
                "relocalisations": report["relocalisations"],
                "map_rms": rms(map_err), "map_max": max(map_err) if map_err else float("nan"),
                "world_rms": rms(world_err),
                "slam_ate": slam["accuracy"]["after_loop_closure"]["ate_rmse_m"],
                "ms": report["ms_per_scan"]["median"], "p95": report["ms_per_scan"]["p95"],
            })
            print(json.dumps(rows[-1]), file=sys.stderr)
    print("| sensor | seed | scans localised | first fix (scan) | re-localisations | error in the "
          "map's frame, RMS / worst (m) | error to the world's truth, RMS (m) | the map's own "
          "ATE after loop closure (m) | ms per scan, median / p95 |")
    print("|---|---|---|---|---|---|---|---|---|")
    for r in rows:
        fix = "never" if r["first_fix"] is None else str(r["first_fix"])
        print(f"| {r['sensor']} | {r['seed']} | {100 * r['localised']:.1f} % | {fix} | "
              f"{r['relocalisations']} | {r['map_rms']:.3f} / {r['map_max']:.3f} | "
              f"{r['world_rms']:.3f} | {r['slam_ate']:.3f} | {r['ms']:.2f} / {r['p95']:.1f} |")
    for sensor in args.sensors:
        rs = [r for r in rows if r["sensor"] == sensor]
        print(f"\n{sensor}: median localised {100 * statistics.median(r['localised'] for r in rs):.1f} %, "
              f"median map-frame RMS {statistics.median(r['map_rms'] for r in rs):.3f} m, "
              f"median ms/scan {statistics.median(r['ms'] for r in rs):.2f}")


if __name__ == "__main__":
    main()
