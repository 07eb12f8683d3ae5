#!/usr/bin/env bash
# Usage: run_commit.sh COMMIT
# Before: worktree /work/wt-cmp checked out at COMMIT and, in it,
#   CARGO_TARGET_DIR=/work/tgt-cmp nice -n 19 cargo build --release -p infer -p dataset_gen -p eval \
#     --features infer/cli --bin plan --bin dataset_gen --bin eval
# The binaries are copied to /work/cmp/COMMIT/bin and COMMIT's artifacts/ exported to
# /work/cmp/COMMIT/src (git archive), and everything runs from there, so the worktree can
# move on to the next commit meanwhile. Outputs in /work/cmp/COMMIT/; step wall times in steps.log.
set -euo pipefail
C=$1
WT=/work/wt-cmp
OUT=/work/cmp/$C
test "$(git -C $WT rev-parse --short=7 HEAD)" = "$C" || { echo "worktree not at $C"; exit 1; }
mkdir -p $OUT/bin
cp /work/tgt-cmp/release/{plan,dataset_gen,eval} $OUT/bin/
rm -rf $OUT/src && mkdir -p $OUT/src && git -C /work/main archive $C artifacts | tar -x -C $OUT/src
WT=$OUT/src
cd $WT
step() { local s=$(date +%s.%N); "$@"; echo "$(date -u +%T) $(echo "$(date +%s.%N) - $s" | bc) s: $*" >> $OUT/steps.log; }
# 2. plans: tasks A-D, network planner and template planner; run twice (rep 1, 2) as a determinism control
for rep in 1 2; do
  for t in A B C D; do
    step nice -n 19 $OUT/bin/plan --task $t --networks $WT/artifacts -o $OUT/plan_${t}_network_r$rep > $OUT/plan_${t}_network_r$rep.stdout 2>&1 || echo "plan $t network exit $?" >> $OUT/steps.log
    step nice -n 19 $OUT/bin/plan --task $t --networks $WT/artifacts --templates $WT/artifacts/templates.json -o $OUT/plan_${t}_templates_r$rep > $OUT/plan_${t}_templates_r$rep.stdout 2>&1 || echo "plan $t templates exit $?" >> $OUT/steps.log
  done
done
for t in A B C D; do for p in network templates; do cp $OUT/plan_${t}_${p}_r1.json $OUT/plan_${t}_${p}.json; done; done
# 3. dataset bytes: same seed, 1 and 2 threads
for th in 1 2; do
  rm -rf $OUT/ds_t$th
  step nice -n 19 $OUT/bin/dataset_gen --threads $th generate --algorithm pso --per-type 24 --part-size 16 --seed 7 --out $OUT/ds_t$th --no-progress > $OUT/ds_t$th.stdout 2> $OUT/ds_t$th.stderr
done
(cd $OUT && find ds_t1 ds_t2 -type f -name '*.mcap' | sort | xargs sha256sum) > $OUT/ds_sha256.txt
# 4. eval pipeline --quick (shipped networks), report and plans kept
rm -rf $OUT/quick
step nice -n 19 $OUT/bin/eval --threads 2 --no-progress pipeline --quick --networks $WT/artifacts --out $OUT/quick --report $OUT/quick/report > $OUT/quick.stdout 2> $OUT/quick.stderr
# 5 (extra, not in issue 23's list): offline sequence PSO + compass polish, small budget, task B
step nice -n 19 $OUT/bin/dataset_gen --threads 2 optimise-task --task B --population 20 --iterations 40 --restarts 2 --polish 1500 --seed 1 --out $OUT/seq_B --no-progress > $OUT/seq_B.stdout 2>&1 || echo "optimise-task exit $?" >> $OUT/steps.log
echo "done $C" >> $OUT/steps.log
