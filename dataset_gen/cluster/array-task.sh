#!/usr/bin/env bash
# One task of a cluster job array that builds a dataset or a plan library
# in a shared folder: task k of n computes shard k/n of the samples
# (`dataset_gen generate --shard k/n`) or of the library's tasks
# (`dataset_gen library --shard k/n`), and the merge task joins them into
# OUT/dataset.mcap or OUT/library.mcap. A task that is killed and run again
# resumes (finished parts and plans are kept, a part another task holds is
# left to it), so preempted or requeued tasks lose and duplicate nothing;
# the merge refuses while parts or plans are missing.
#
#   array-task.sh shard|library   # k from SLURM_ARRAY_TASK_ID, JOB_COMPLETION_INDEX (Kubernetes) or ARRAY_INDEX
#   array-task.sh merge|library-merge
#
# Settings, from the environment:
#   SHARDS       n, the number of array tasks (required)
#   OUT          the shared output folder (default runs/dataset, runs/library)
#   SEED, PER_TYPE, ALGORITHM, ITERATIONS, POPULATION, PART_SIZE   as `dataset_gen generate`
#   TASKS, SEED, WIDE=1, ANCHORS, NEIGHBOURS, RADIUS, WARM_ITERATIONS, WAVE, OPTIMISER, DIGS, POPULATION, ITERATIONS,
#   RESTARTS, POLISH   as `dataset_gen library` (a warm library, ANCHORS set, runs
#   the array twice: WAVE=anchors, then WAVE=warm)
#   DATASET_GEN  the dataset_gen binary (default: dataset_gen on PATH)
set -euo pipefail

bin=${DATASET_GEN:-dataset_gen}
fail() { echo "error: $*" >&2; exit 2; }

[[ ${SHARDS:-} =~ ^[1-9][0-9]*$ ]] || fail "SHARDS must be a positive whole number (got '${SHARDS:-}')"

index() {
    k=${SLURM_ARRAY_TASK_ID:-${JOB_COMPLETION_INDEX:-${ARRAY_INDEX:-}}}
    [[ $k =~ ^[0-9]+$ ]] || fail "no array index: set SLURM_ARRAY_TASK_ID, JOB_COMPLETION_INDEX or ARRAY_INDEX"
    ((k < SHARDS)) || fail "array index $k is not below SHARDS=$SHARDS"
}

case ${1:-} in
shard)
    out=${OUT:-runs/dataset}
    index
    args=(generate --shard "$k/$SHARDS" --out "$out" --no-progress
        --seed "${SEED:-1}" --per-type "${PER_TYPE:-1800}" --algorithm "${ALGORITHM:-pso}"
        --iterations "${ITERATIONS:-100}" --part-size "${PART_SIZE:-64}")
    [[ -n ${POPULATION:-} ]] && args+=(--population "$POPULATION")
    exec "$bin" "${args[@]}"
    ;;
merge)
    out=${OUT:-runs/dataset}
    exec "$bin" merge --out "$out/dataset.mcap" "$out"
    ;;
library)
    out=${OUT:-runs/library}
    index
    args=(library --shard "$k/$SHARDS" --out "$out" --no-progress
        --tasks "${TASKS:-1000}" --seed "${SEED:-7}")
    [[ ${WIDE:-} == 1 ]] && args+=(--wide)
    for v in ANCHORS NEIGHBOURS RADIUS WARM_ITERATIONS WAVE OPTIMISER DIGS POPULATION ITERATIONS RESTARTS POLISH; do
        flag=${v,,}
        [[ -n ${!v:-} ]] && args+=("--${flag//_/-}" "${!v}")
    done
    exec "$bin" "${args[@]}"
    ;;
library-merge)
    exec "$bin" library-merge --out "${OUT:-runs/library}"
    ;;
*)
    fail "usage: array-task.sh shard|merge|library|library-merge"
    ;;
esac
