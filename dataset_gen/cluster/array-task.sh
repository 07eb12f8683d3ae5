#!/usr/bin/env bash
# One task of a cluster job array that builds a dataset in a shared folder:
# task k of n computes shard k/n of the samples (`dataset_gen generate
# --shard k/n`), and the merge task joins the parts into OUT/dataset.mcap.
# A task that is killed and run again resumes (finished parts are kept, a
# part another task holds is left to it), so preempted or requeued tasks
# lose and duplicate nothing; the merge refuses while parts are missing.
#
#   array-task.sh shard   # k from SLURM_ARRAY_TASK_ID, JOB_COMPLETION_INDEX (Kubernetes) or ARRAY_INDEX
#   array-task.sh merge
#
# Settings, from the environment:
#   SHARDS       n, the number of array tasks (required)
#   OUT          the shared output folder (default runs/dataset)
#   SEED, PER_TYPE, ALGORITHM, ITERATIONS, POPULATION, PART_SIZE   as `dataset_gen generate`
#   DATASET_GEN  the dataset_gen binary (default: dataset_gen on PATH)
set -euo pipefail

bin=${DATASET_GEN:-dataset_gen}
out=${OUT:-runs/dataset}
fail() { echo "error: $*" >&2; exit 2; }

[[ ${SHARDS:-} =~ ^[1-9][0-9]*$ ]] || fail "SHARDS must be a positive whole number (got '${SHARDS:-}')"

case ${1:-} in
shard)
    k=${SLURM_ARRAY_TASK_ID:-${JOB_COMPLETION_INDEX:-${ARRAY_INDEX:-}}}
    [[ $k =~ ^[0-9]+$ ]] || fail "no array index: set SLURM_ARRAY_TASK_ID, JOB_COMPLETION_INDEX or ARRAY_INDEX"
    ((k < SHARDS)) || fail "array index $k is not below SHARDS=$SHARDS"
    args=(generate --shard "$k/$SHARDS" --out "$out" --no-progress
        --seed "${SEED:-1}" --per-type "${PER_TYPE:-1800}" --algorithm "${ALGORITHM:-pso}"
        --iterations "${ITERATIONS:-100}" --part-size "${PART_SIZE:-64}")
    [[ -n ${POPULATION:-} ]] && args+=(--population "$POPULATION")
    exec "$bin" "${args[@]}"
    ;;
merge)
    exec "$bin" merge --out "$out/dataset.mcap" "$out"
    ;;
*)
    fail "usage: array-task.sh shard|merge"
    ;;
esac
