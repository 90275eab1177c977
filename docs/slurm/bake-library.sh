#!/bin/bash
# One shard of a material library per Slurm array task (docs/scale-out.md):
#   sbatch --array=0-7 docs/slurm/bake-library.sh LIB.json /shared/ganzfeld-cache
# The array must be 0..N-1 with step 1: task K of N bakes shard K/N. Every task writes straight
# into the shared cache: the shards' file names are disjoint and each file appears by an atomic
# rename, so no task sees another's partial file. Re-submitting the array after a failure re-bakes
# only what is missing (an existing entry with the right key is reused).
#SBATCH --job-name=ganzfeld-bake
#SBATCH --cpus-per-task=8
#SBATCH --mem=4G
#SBATCH --time=02:00:00
#SBATCH --output=ganzfeld-bake-%A_%a.log
set -euo pipefail
LIBRARY="${1:?usage: sbatch --array=0-N1 bake-library.sh LIB.json CACHE_DIR}"
CACHE="${2:?usage: sbatch --array=0-N1 bake-library.sh LIB.json CACHE_DIR}"
K="${SLURM_ARRAY_TASK_ID:?run as an array job: sbatch --array=0-7 ...}"
N="${SLURM_ARRAY_TASK_COUNT:?run as an array job: sbatch --array=0-7 ...}"
# Task ids must be exactly 0..N-1 (not 1-8, not 0-14:2): otherwise shards would be skipped.
if [ "${SLURM_ARRAY_TASK_MIN:-0}" -ne 0 ] || [ "${SLURM_ARRAY_TASK_MAX:-$((N - 1))}" -ne $((N - 1)) ]; then
  echo "bake-library.sh: submit with --array=0-$((N - 1)) (ids 0 to N-1, step 1)" >&2
  exit 2
fi
# The bake runs its entries on every core of the task's CPU set (TBB follows the affinity mask
# Slurm gives the task: --cpus-per-task).
exec ganzfeld bake library "$LIBRARY" --out "$CACHE" --shard "$K/$N" --quiet
