#!/bin/bash
# scripts/experiments/common.sh reads what rlt train wrote: `machines` names the CPU, cores and
# OpenBLAS kernels of a real run's session (the status file's format and the helper's pattern must
# agree), says "unrecorded" for a status file from before sessions, and `emerged` reads a strategy.
# Usage: experiments_common_test.sh RLT_BINARY SOURCE_DIR
set -eu
rlt=$1
source_dir=$2
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
"$rlt" train "$source_dir/configs/cartpole_ppo.yaml" --max-steps 300 --results-dir "$dir/runs" \
  --run-id new --threads 1 > /dev/null
mkdir -p "$dir/runs/old"
echo '{"run_id": "old", "finished": true, "strategies": {"shelter": {"metric": "fort_rate", "behavior": "Hider", "emerged": true, "step": 2372942, "elapsed_seconds": 2154.0, "rate": 0.51}}}' \
  > "$dir/runs/old/training_status.json"
RESULTS=$dir/runs REPORTS=$dir/reports
source "$source_dir/scripts/experiments/common.sh"
cpu=$(grep -m1 '^model name' /proc/cpuinfo | sed 's/^[^:]*: *//')
got=$(machines new)
echo "machines new: $got"
case "$got" in
  "${cpu:-unknown} ($(nproc) cores, OpenBLAS "?*")") ;;
  *) echo "expected '$cpu ($(nproc) cores, OpenBLAS <kernels>)'" >&2; exit 1 ;;
esac
got=$(machines old)
echo "machines old: $got"
[ "$got" = unrecorded ]
[ "$(emerged old shelter)" = 2372942 ]
