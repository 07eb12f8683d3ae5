#!/usr/bin/env bash
# The whole-task sequence search with each optimiser at equal evaluations:
# tasks A-D, 4 restarts of 100 x 300 (CMA-ES: 20 x 1,500), no compass polish,
# seeds 1-3. Prints one row per run (task, optimiser, seed, under-dug,
# over-dug) and then the median of under- plus over-dug per task.
# Usage: dataset_gen/scripts/sequence_optimisers.sh [OUT_DIR]  (after cargo build --release -p dataset_gen)
set -euo pipefail
cd "$(dirname "$0")/../.."
out=${1:-runs/sequence_optimisers}
mkdir -p "$out"
rows="$out/runs.txt"
: > "$rows"
for task in A B C D; do
  for seed in 1 2 3; do
    for cfg in "pso 100 300" "pso-v10 100 300" "cmaes 20 1500" "gwo 100 300"; do
      set -- $cfg
      json=$(target/release/dataset_gen optimise-task --task "$task" --optimiser "$1" \
        --population "$2" --iterations "$3" --restarts 4 --polish 0 --seed "$seed" \
        --out "$out/${task}_$1_$seed" 2>/dev/null || echo '{}')
      echo "$task $1 $seed $(echo "$json" | python3 -c 'import json,sys; d=json.load(sys.stdin); print(d.get("under_dug","failed"), d.get("over_dug",""))')" | tee -a "$rows"
    done
  done
done
python3 - "$rows" <<'PY'
import statistics, sys
runs = {}
for line in open(sys.argv[1]):
    task, opt, seed, *v = line.split()
    runs.setdefault((task, opt), []).append(None if v[0] == "failed" else float(v[0]) + float(v[1]))
opts = ["pso", "pso-v10", "cmaes", "gwo"]
print("| task | " + " | ".join(opts) + " |\n|---" * 1 + "|---" * len(opts) + "|")
for task in "ABCD":
    cells = []
    for o in opts:
        ok = [x for x in runs[(task, o)] if x is not None]
        failed = len(runs[(task, o)]) - len(ok)
        cell = f"{100 * statistics.median(ok):.1f} %" if ok else "-"
        cells.append(cell + (f" ({failed} failed)" if failed else ""))
    print(f"| {task} | " + " | ".join(cells) + " |")
PY
