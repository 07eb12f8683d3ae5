#!/bin/sh
# The perception chain on one core, Rust (`perceive --threads 1`) against
# Open3D (scripts/perception_open3d.py, OMP_NUM_THREADS=1), alternated
# 5 times on the same generated typical scan; prints each run's total (s).
# Usage: dataset_gen/scripts/compare_open3d.sh target/release/perceive
set -e
PERCEIVE=${1:-target/release/perceive}
DIR=$(mktemp -d)
"$PERCEIVE" --pile typical --seed 1 --write-ply "$DIR/scan.ply" > "$DIR/gen.json"
for i in 1 2 3 4 5; do
  "$PERCEIVE" --threads 1 --ply "$DIR/scan.ply" --config /dev/stdin > "$DIR/rust.json" <<JSON
$(python3 -c "import json,sys; print(json.dumps(json.load(open('$DIR/gen.json'))['config']))")
JSON
  python3 -c "import json; d=json.load(open('$DIR/rust.json')); print('rust', sum(s['millis'] for s in d['steps'])/1e3, d['r_squared'])"
  OMP_NUM_THREADS=1 python3 "$(dirname "$0")/perception_open3d.py" "$DIR/scan.ply" "$DIR/gen.json" \
    | python3 -c "import json,sys; d=json.load(sys.stdin); print('open3d', d['total_s'], d['r_squared'])"
done
rm -rf "$DIR"
