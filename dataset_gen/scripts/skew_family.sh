#!/usr/bin/env bash
# The dig family with and without the skew a_i7 (infer/src/trajectory.rs):
# the whole-task sequence search (`optimise-task`, default CMA-ES settings,
# seed 1) on tasks A-D and 12 fresh tasks drawn from issue 26's wide range
# (L 0.40-0.85 m, D 0.06-0.20 m, beta 30-75 deg, far edge 0.98-1.10 m;
# Python's random.Random(26), listed below so no Python is needed to rerun).
# Prints one row per run (task, family, under-dug, over-dug, seconds), then
# a summary per family over the tasks both planned.
# Usage: dataset_gen/scripts/skew_family.sh [OUT_DIR]  (after cargo build --release -p dataset_gen)
set -euo pipefail
cd "$(dirname "$0")/../.."
out=${1:-runs/skew_family}
mkdir -p "$out"
rows="$out/runs.txt"
: > "$rows"
tasks=(
  "A --task A" "B --task B" "C --task C" "D --task D"
  "f01 -L 0.736 -D 0.088 --slope-far 39.2 --slope-near 57.0 --far-edge 0.987"
  "f02 -L 0.749 -D 0.167 --slope-far 31.9 --slope-near 60.8 --far-edge 1.040"
  "f03 -L 0.686 -D 0.194 --slope-far 74.4 --slope-near 48.4 --far-edge 1.081"
  "f04 -L 0.754 -D 0.196 --slope-far 31.3 --slope-near 72.2 --far-edge 1.007"
  "f05 -L 0.458 -D 0.144 --slope-far 67.7 --slope-near 73.1 --far-edge 1.024"
  "f06 -L 0.772 -D 0.064 --slope-far 73.6 --slope-near 43.2 --far-edge 1.045"
  "f07 -L 0.456 -D 0.066 --slope-far 30.3 --slope-near 57.0 --far-edge 1.047"
  "f08 -L 0.767 -D 0.179 --slope-far 49.1 --slope-near 68.1 --far-edge 1.004"
  "f09 -L 0.796 -D 0.095 --slope-far 72.3 --slope-near 47.3 --far-edge 1.031"
  "f10 -L 0.633 -D 0.068 --slope-far 33.4 --slope-near 54.5 --far-edge 1.066"
  "f11 -L 0.420 -D 0.117 --slope-far 46.6 --slope-near 65.2 --far-edge 1.099"
  "f12 -L 0.441 -D 0.136 --slope-far 34.7 --slope-near 65.3 --far-edge 1.093"
)
for t in "${tasks[@]}"; do
  set -- $t
  name=$1
  shift
  for family in spec skew; do
    flag=()
    [ "$family" = skew ] && flag=(--skew)
    json=$(target/release/dataset_gen optimise-task "$@" "${flag[@]}" --seed 1 --no-progress \
      --out "$out/${name}_$family" 2>/dev/null || echo '{}')
    echo "$name $family $(echo "$json" | python3 -c 'import json,sys; d=json.load(sys.stdin); print(d.get("under_dug","failed"), d.get("over_dug",""), round(d.get("planning_seconds",0),1))')" | tee -a "$rows"
  done
done
python3 - "$rows" <<'PY'
import statistics, sys
runs = {}
for line in open(sys.argv[1]):
    name, family, *v = line.split()
    runs.setdefault(name, {})[family] = None if v[0] == "failed" else (float(v[0]), float(v[1]))
both = [n for n, r in runs.items() if r.get("spec") and r.get("skew")]
print(f"{len(both)} of {len(runs)} tasks planned in both families")
print("| family | under-dug median | mean | worst | over-dug worst | tasks with both ≤ 3 % |\n|---|---|---|---|---|---|")
for family in ["spec", "skew"]:
    u = [runs[n][family][0] for n in both]
    o = [runs[n][family][1] for n in both]
    ok = sum(1 for n in both if max(runs[n][family]) <= 0.03)
    print(f"| {family} | {100*statistics.median(u):.2f} % | {100*statistics.mean(u):.2f} % | {100*max(u):.2f} % | {100*max(o):.2f} % | {ok} of {len(both)} |")
PY
