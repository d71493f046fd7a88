#!/usr/bin/env bash
# A large clapping-chart sweep as a Slurm job array: 64 shards, each one job.
#
#   sbatch examples/slurm-chart.sh          # submits shards 1..64
#   clapper merge --csv sweep.csv sweep-part-*.csv    # once all have finished
#
# A shard that is killed (pre-emption, time limit) resumes where it stopped
# when it runs again with the same options: resubmit it with
# `sbatch --array=17 examples/slurm-chart.sh`.
#SBATCH --job-name=clapper-chart
#SBATCH --array=1-64
#SBATCH --cpus-per-task=8
#SBATCH --time=02:00:00
#SBATCH --output=sweep-part-%a.log
set -euo pipefail
N=64
clapper chart \
  --grid 2000 --theta0 90,120,150,171 --restitution 0.1,0.2,0.3 \
  --threads "${SLURM_CPUS_PER_TASK:-1}" \
  --shard "${SLURM_ARRAY_TASK_ID}/${N}" \
  --csv "sweep-part-${SLURM_ARRAY_TASK_ID}.csv"
