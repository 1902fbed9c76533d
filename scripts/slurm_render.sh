#!/usr/bin/env bash
# scripts/slurm_render.sh — one shard of an `aquarelle render --frames/--sweep` job per Slurm array
# task (docs/shards.md). The array's size is the shard count; each task renders
# `--shard TASK_ID/COUNT` with the task's CPUs. Output paths must be on storage every node sees.
#
#   sbatch --array=0-15 --cpus-per-task=2 scripts/slurm_render.sh \
#       scenes/data/oak.json --style ld06 --frames 0-239 --orbit 1.5 --out /shared/oak/f_####.png
#
# AQ_BIN overrides the binary (default: build/app/aquarelle of the submit directory).
#SBATCH --job-name=aquarelle
#SBATCH --cpus-per-task=2
set -euo pipefail
task=${SLURM_ARRAY_TASK_ID:?run through sbatch --array=0-(N-1) (no SLURM_ARRAY_TASK_ID)}
count=${SLURM_ARRAY_TASK_COUNT:-$(( ${SLURM_ARRAY_TASK_MAX:?no SLURM_ARRAY_TASK_MAX} + 1 ))}
[ "${SLURM_ARRAY_TASK_MIN:-0}" = 0 ] || { echo "slurm_render.sh: the array must start at 0" >&2; exit 2; }
cd "${SLURM_SUBMIT_DIR:-.}"
exec "${AQ_BIN:-build/app/aquarelle}" render "$@" --shard "$task/$count" --threads "${SLURM_CPUS_PER_TASK:-0}"
