#!/usr/bin/env bash
# Runs a sweep on a Slurm cluster as a job array of N shards, then merges them.
#
# Submit (from a login node, in the repository, with tcgen built):
#   scripts/slurm_sweep.sh tables/nightly_random_two_sided.toml out/random.h5 16
# submits an array of 16 tasks (shard i of 16 each, `tcgen sweep --shard i/16
# --resume`, so a requeued or timed-out task continues from its checkpoint) and
# a merge job that runs after all of them succeeded (`tcgen merge`). The
# shards are written beside the output as <output>.shard-<i>-of-<n>.h5.
#
# Environment: TCGEN (the binary, default target/release/tcgen),
# SBATCH_ARGS (extra sbatch options, e.g. "--partition=short --time=04:00:00"),
# CPUS (cores per task, default 2).
# Give tasks memory with SBATCH_ARGS="--mem=…": tcgen reads the task's
# control-group limit and refuses what would not fit there (schemas/case.md).
set -euo pipefail
if [ -n "${SLURM_ARRAY_TASK_ID:-}" ] && [ "${TCGEN_SLURM_ROLE:-}" = shard ]; then
    # One shard (inside the array job).
    i="$SLURM_ARRAY_TASK_ID"
    exec "$TCGEN" sweep "$CONFIG" -o "$OUTPUT.shard-$i-of-$SHARDS.h5" \
        --shard "$i/$SHARDS" --resume --progress log --threads "${SLURM_CPUS_PER_TASK:-1}"
fi
if [ "${TCGEN_SLURM_ROLE:-}" = merge ]; then
    shards=()
    for ((i = 0; i < SHARDS; i++)); do shards+=("$OUTPUT.shard-$i-of-$SHARDS.h5"); done
    exec "$TCGEN" merge "${shards[@]}" -o "$OUTPUT"
fi
if [ $# -ne 3 ]; then
    echo "usage: $0 SWEEP.toml OUTPUT.h5 SHARDS" >&2
    exit 2
fi
root="$(cd "$(dirname "$0")/.." && pwd)"
export CONFIG="$(realpath "$1")" OUTPUT="$(realpath -m "$2")" SHARDS="$3"
export TCGEN="$(realpath "${TCGEN:-${CARGO_TARGET_DIR:-$root/target}/release/tcgen}")"
mkdir -p "$(dirname "$OUTPUT")"
# shellcheck disable=SC2086
array=$(TCGEN_SLURM_ROLE=shard sbatch --parsable --export=ALL --array=0-$((SHARDS - 1)) \
    --cpus-per-task="${CPUS:-2}" --job-name=tcgen-sweep ${SBATCH_ARGS:-} "$0")
# shellcheck disable=SC2086
merge=$(TCGEN_SLURM_ROLE=merge sbatch --parsable --export=ALL --dependency=afterok:"$array" \
    --job-name=tcgen-merge ${SBATCH_ARGS:-} "$0")
echo "submitted shards $array (0-$((SHARDS - 1))) and merge $merge -> $OUTPUT"
