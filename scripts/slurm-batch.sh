#!/bin/bash
#SBATCH --job-name=splatcl-batch
#SBATCH --array=0-15
#SBATCH --cpus-per-task=8
#SBATCH --mem=8G
#SBATCH --time=04:00:00
#SBATCH --requeue
#SBATCH --output=splatcl-batch-%A-%a.log
# Run from the project folder on the shared file system: set.json and out/ are relative to it, and
# so is the log (Slurm opens it before the script starts, so it cannot be in a folder yet to be made).
# PoCL's compiled kernels go to node-local storage, not the shared home (below).
export POCL_CACHE_DIR="${TMPDIR:-/tmp}/pocl-cache-$USER"
srun splatcl batch set.json -o out --shard "$SLURM_ARRAY_TASK_ID/$SLURM_ARRAY_TASK_COUNT"
