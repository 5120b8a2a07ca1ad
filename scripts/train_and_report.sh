#!/usr/bin/env bash
# The main job behind `make train`: trains a configuration (default: the drone hide-and-seek),
# then shows what was learned: the exported policies, the emergent-strategy metrics of the trained
# hiders against their own seekers, against random seekers and of the trained seekers against
# still hiders, and a recorded evaluation episode for replay viewers.
#
# Usage: scripts/train_and_report.sh CONFIG RUN_ID [rlt train options, e.g. --max-steps 200000]
set -euo pipefail
cd "$(dirname "$0")/.."
RLT=./build/apps/rlt
CONFIG=$1
RUN_ID=$2
shift 2
RESULTS=results
RUN=$RESULTS/$RUN_ID

"$RLT" train "$CONFIG" --run-id "$RUN_ID" --results-dir "$RESULTS" "$@"

echo
echo "Exported policies:"
ls -1 "$RUN"/*.pt | sed 's/^/  /'

# behaviors and whether the env records episodes (the drone envs do)
ENV_ID=$(sed -n 's/^  env_id: *//p' "$RUN/configuration.yaml" | head -n 1)
EPISODES=${EVAL_EPISODES:-20}

# prints "label: key value, ..." from the JSON lines of rlt eval
summarize() {
  local label=$1
  shift
  echo "  $label"
  "$RLT" eval "$RUN" --episodes "$EPISODES" --json "$@" |
    sed -e 's/[{}"]//g' -e 's/,/ /g' -e 's/:/ /g' |
    awk '{ line = "    "; for (i = 1; i < NF; i += 2) {
             if ($i == "behavior" || $i == "policy") continue;
             line = line sprintf("%s %s  ", $i, $(i + 1)) }
           print $2 " (" $4 "): " substr(line, 5) }' | sed 's/^/    /'
}

echo
echo "Evaluation, $EPISODES episodes each (rlt eval $RUN ...):"
if [ "$ENV_ID" = "HideAndSeek" ]; then
  summarize "trained hiders vs trained seekers"
  summarize "trained hiders vs random seekers" --policy Seeker=random
  summarize "trained seekers vs still hiders" --policy Hider=still
else
  summarize "trained policies"
fi

if [ "$ENV_ID" = "HideAndSeek" ]; then
  "$RLT" eval "$RUN" --episodes 1 --record "$RUN/replay.json" > /dev/null
  echo
  echo "Replay of one evaluation episode: $RUN/replay.json (watch it: $RLT replay $RUN/replay.json)"
fi
"$RLT" plot "$RUN" > /dev/null && echo "Learning curves: $RUN/plots/ (rlt plot)"
echo "Strategies (training_status.json):"
sed -n '/"strategies"/,/^  }/p' "$RUN/training_status.json" | sed '1d;$d'
