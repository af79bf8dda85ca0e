#!/usr/bin/env bash
# Registers the real KITTI
# city drive shipped beside the project (../shared/data/kitti_city_seq, 22 HDL-64 sweeps):
# every consecutive pair is registered with dlo-register, and the 3-DoF poses are chained into
# the trajectory of the drive (about 17 m, almost straight).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install_deps.sh
bash scripts/build.sh

SEQ="${1:-../shared/data/kitti_city_seq}"
if [ ! -d "$SEQ" ]; then
  echo "run_kitti_demo: sequence folder '$SEQ' not found (expected ../shared/data/kitti_city_seq)." >&2
  exit 1
fi
OUT="${DLO_DEMO_OUT:-out/kitti_demo}"
mkdir -p "$OUT"
REGISTER=build/apps/dlo-register/dlo-register
mapfile -t FRAMES < <(ls "$SEQ"/*.bin* | sort)
echo "run_kitti_demo: registering ${#FRAMES[@]} frames of $SEQ (3-DoF, constant-velocity guess)"
: > "$OUT/pairs.jsonl"
init="0 0 0 0 0 0"
for ((i = 1; i < ${#FRAMES[@]}; i++)); do
  json=$("$REGISTER" "${FRAMES[i - 1]}" "${FRAMES[i]}" --dof 3 --init "$init")
  echo "$json" >> "$OUT/pairs.jsonl"
  # Constant velocity: the next pair starts from this pair's motion.
  x=$(sed -E 's/.*"x": ?([-0-9.e+]+).*/\1/' <<< "$json")
  y=$(sed -E 's/.*"y": ?([-0-9.e+]+).*/\1/' <<< "$json")
  yaw=$(sed -E 's/.*"yaw_deg": ?([-0-9.e+]+).*/\1/' <<< "$json")
  init="$x $y 0 $yaw 0 0"
done
awk -F'[:,{}]+' '
  function val(key,   k) { for (k = 1; k < NF; k++) if ($k ~ "\"" key "\"$") return $(k + 1); return 0 }
  BEGIN { X = 0; Y = 0; TH = 0; pi = atan2(0, -1); printf "%5s %8s %8s %8s %8s %8s %6s %9s\n", "pair", "dx", "dy", "dyaw", "X", "Y", "cells", "total_ms" }
  {
    dx = val("x"); dy = val("y"); dyaw = val("yaw_deg") * pi / 180
    X += cos(TH) * dx - sin(TH) * dy; Y += sin(TH) * dx + cos(TH) * dy; TH += dyaw
    printf "%5d %8.3f %8.3f %8.3f %8.2f %8.2f %6d %9.2f\n", NR, dx, dy, val("yaw_deg"), X, Y, val("cells"), val("total")
    printf "%d %.6f %.6f 0 0 0 %.9f %.9f\n", NR, X, Y, sin(TH / 2), cos(TH / 2) > "'"$OUT"'/trajectory.tum"
  }
  END { printf "run_kitti_demo: %d pairs, travelled %.2f m, final heading %.2f deg; trajectory in %s\n", NR, sqrt(X * X + Y * Y), TH * 180 / pi, "'"$OUT"'/trajectory.tum" }
' "$OUT/pairs.jsonl"
