#!/usr/bin/env bash
# Queues a dataset as a Slurm job array of SHARDS tasks and its merge, which
# runs only once every shard has succeeded. Run from the repository's top,
# with OUT on a file system every node shares:
#
#   SHARDS=8 OUT=/shared/runs/dataset SEED=1 PER_TYPE=1800 \
#     DATASET_GEN=$PWD/target/release/dataset_gen dataset_gen/cluster/slurm/submit.sh
#
# A plan library the same way (JOB=library; TASKS, WIDE=1 and the sequence
# settings as array-task.sh lists them):
#
#   JOB=library SHARDS=16 OUT=/shared/runs/library TASKS=1000 WIDE=1 \
#     DATASET_GEN=$PWD/target/release/dataset_gen dataset_gen/cluster/slurm/submit.sh
#
# A warm library (ANCHORS=N: tasks 1..N searched cold, the rest refitted
# from them) is queued as two arrays, the warm one after every anchor shard:
#
#   JOB=library ANCHORS=100 SHARDS=16 OUT=/shared/runs/library TASKS=1000 WIDE=1 \
#     DATASET_GEN=$PWD/target/release/dataset_gen dataset_gen/cluster/slurm/submit.sh
#
# A failed or preempted shard can be resubmitted alone (sbatch --array=K …):
# it resumes from the parts (or plans) it finished.
set -euo pipefail
here=dataset_gen/cluster/slurm
[[ ${SHARDS:-} =~ ^[1-9][0-9]*$ ]] || { echo "error: set SHARDS (a positive whole number)" >&2; exit 2; }
array=(sbatch --parsable --export=ALL --array=0-$((SHARDS - 1)))
if [[ ${JOB:-} == library && -n ${ANCHORS:-} ]]; then
    anchors=$(WAVE=anchors "${array[@]}" "$here/shard.sbatch")
    jid=$(WAVE=warm "${array[@]}" --dependency=afterok:"$anchors" "$here/shard.sbatch")
    echo "anchors: job $anchors; the warm tasks follow when all succeed" >&2
else
    jid=$("${array[@]}" "$here/shard.sbatch")
fi
sbatch --parsable --export=ALL --dependency=afterok:"$jid" "$here/merge.sbatch"
echo "shards: job $jid (array 0-$((SHARDS - 1))); the merge follows when all succeed" >&2
