#!/usr/bin/env bash
# README command (1): install what is missing, build, and run the main job: dlo-slam on a
# simulated HDL-64 drive with a closed loop (300 sweeps, about 30 s to simulate), printing the
# accuracy against the simulator's ground truth before and after loop closure.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install_deps.sh
bash scripts/build.sh

OUT="${DLO_DEMO_OUT:-out/demo}"
FRAMES="${DLO_DEMO_FRAMES:-300}"
mkdir -p "$OUT"
SIMULATE=build/apps/dlo-simulate/dlo-simulate
# Simulate unless the same sequence is already there (same length, from this simulator build).
if [ ! -s "$OUT/sim/groundtruth.tum" ] || [ "$SIMULATE" -nt "$OUT/sim/groundtruth.tum" ] ||
  [ "$(grep -vc '^#' "$OUT/sim/groundtruth.tum")" != "$FRAMES" ]; then
  echo "run_demo: simulating $FRAMES HDL-64 sweeps into $OUT/sim"
  "$SIMULATE" --out "$OUT/sim" --frames "$FRAMES" --sensor HDL64 --seed 1
fi
echo "run_demo: dlo-slam on $OUT/sim/sequence.rawlog"
build/apps/dlo-slam/dlo-slam --input "$OUT/sim/sequence.rawlog" --out "$OUT/slam" \
  --gt "$OUT/sim/groundtruth.tum"

# The accuracy block of report.json, one line per phase.
python3 - "$OUT/slam/report.json" <<'PY'
import json, sys
accuracy = json.load(open(sys.argv[1]))["accuracy"]
for phase in ("before_loop_closure", "after_loop_closure"):
    values = ", ".join(f"{k}: {v:.6g}" if v is not None else f"{k}: null"
                       for k, v in accuracy[phase].items())
    print(f"run_demo: {phase}: {values}")
PY
echo "run_demo: outputs (trajectory, pose graph, simplemap, height map, PLY, 3D scene, report)" \
  "in $OUT/slam"
