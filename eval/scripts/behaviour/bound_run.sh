#!/usr/bin/env bash
# Extra probe: plans A-D of both commits under an evaluation bound (max_evaluations 320).
set -eu
cd /work/cmp
for c in 8ea9a58 471cf30; do for t in A B C D; do
  nice -n 19 $c/bin/plan --task $t --networks $c/src/artifacts --settings bound/settings.json -o bound/${c}_$t > bound/${c}_$t.stdout 2>&1
done; done
