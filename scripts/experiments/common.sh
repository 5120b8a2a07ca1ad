# Shared by the experiment scripts (sourced, not run): training runs that are reused when they
# already finished, and their learning curves drawn by `rlt plot` (gnuplot, installed from Debian
# when missing).
# Environment: RESULTS (run folders, default results/experiments), REPORTS (default docs/results),
# SEEDS (default 1), STEPS (each script's own default).
set -euo pipefail
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)
RLT=$ROOT/build/apps/rlt
RESULTS=${RESULTS:-$ROOT/results/experiments}
REPORTS=${REPORTS:-$ROOT/docs/results}
SEEDS=${SEEDS:-1}
mkdir -p "$RESULTS" "$REPORTS"

ensure_built() {
  [ -x "$RLT" ] || "$ROOT/scripts/setup.sh"
}

ensure_gnuplot() {
  command -v gnuplot > /dev/null && return
  local sudo=""
  [ "$(id -u)" -eq 0 ] || sudo=sudo
  $sudo apt-get install -y --no-install-recommends gnuplot-nox
}

# train_run CONFIG RUN_ID [rlt train options]: trains unless RUN_ID already finished; a stopped
# run is resumed
train_run() {
  local config=$1 run_id=$2
  shift 2
  local status=$RESULTS/$run_id/training_status.json
  if [ -f "$status" ] && grep -q '"finished": true' "$status"; then
    echo "reusing finished run $RESULTS/$run_id"
    return
  fi
  local mode=()
  [ -f "$status" ] && mode=(--resume)
  "$RLT" train "$config" --run-id "$run_id" --results-dir "$RESULTS" "${mode[@]}" "$@" |
    tee -a "$RESULTS/$run_id.log"
}

# column NAME CSV: the 1-based index of column NAME in the CSV's header
column() {
  head -n 1 "$2" | tr ',' '\n' | grep -n -x "$1" | cut -d: -f1
}

# recent_return CSV: a behavior's mean return over the episodes of its last 10 updates
# (metrics/BEHAVIOR.csv: episodes in column 3, mean return in column 4; one update's are too few)
recent_return() {
  tail -n 10 "$1" | awk -F, '$3 > 0 { r += $3 * $4; n += $3 } END { printf "%.3f", r / n }'
}

# json_number LINE KEY: KEY's number in the one-line JSON object LINE (rlt eval --json), to two
# decimals
json_number() {
  echo "$1" | grep -o "\"$2\":[-0-9.e+]*" | cut -d: -f2 | awk '{ printf "%.2f", $1 }'
}

# emerged RUN_ID STRATEGY: the step STRATEGY emerged at in the run, or "not emerged"
emerged() {
  local status=$RESULTS/$1/training_status.json
  local line
  line=$(grep -o "\"$2\": {[^}]*}" "$status")
  if echo "$line" | grep -q '"emerged": true'; then
    echo "$line" | sed 's/.*"step": \([0-9]*\).*/\1/'
  else
    echo "not emerged"
  fi
}

# machines RUN_ID: the CPUs and OpenBLAS kernels the run's sessions ran on, "unrecorded" for runs
# from before training_status.json recorded them. A seed's figures hold on one machine only.
machines() {
  local status=$RESULTS/$1/training_status.json
  local found
  found=$({ grep -o '"cpu": "[^"]*", "cores": [0-9]*, "blas_kernels": "[^"]*"' "$status" || true; } |
    sed 's/"cpu": "\([^"]*\)", "cores": \([0-9]*\), "blas_kernels": "\([^"]*\)"/\1 (\2 cores, OpenBLAS \3)/' |
    sort -u | paste -sd ';' - | sed 's/;/; /g')
  echo "${found:-unrecorded}"
}

# emerged_minutes RUN_ID STRATEGY: training minutes when STRATEGY emerged
emerged_minutes() {
  local status=$RESULTS/$1/training_status.json
  { grep -o "\"$2\": {[^}]*}" "$status" | grep -o '"elapsed_seconds": [0-9.e+]*' || true; } |
    awk '{ printf "%.1f", $2 / 60 }'
}

# plot OUT_DIR RUN_ID...: the runs' learning curves side by side (rlt plot) in OUT_DIR
plot() {
  local out=$1
  shift
  local runs=()
  for run_id in "$@"; do runs+=("$RESULTS/$run_id"); done
  # a run too short to have data leaves the plots out, not the report
  "$RLT" plot "${runs[@]}" --out "$out" > /dev/null || echo "no plots in $out" >&2
}
