#!/usr/bin/env bash
# RQ3: do penalties slow learning? Seekers with a constant penalty per test-phase frame in which no
# hider is seen (--param unseen_reward=PENALTY, default -0.001) against the default configuration
# (no penalty), STEPS per behavior (default 1.6M, the paper's chasing figure), seeds in SEEDS.
# Writes docs/results/rq3_unseen_penalty.md. Compares the seekers' tag rate, not their reward
# (the penalty changes the reward's scale).
source "$(dirname "$0")/common.sh"
ensure_built
ensure_gnuplot
STEPS=${STEPS:-1600000}
PENALTY=${PENALTY:--0.001}
report=$REPORTS/rq3_unseen_penalty.md
{
  echo "# RQ3: a constant penalty for seekers while no hider is seen"
  echo
  echo "Produced by \`scripts/experiments/rq3_unseen_penalty.sh\` on $(date -u +%Y-%m-%d): the"
  echo "default configuration with and without \`--param unseen_reward=$PENALTY\`, $STEPS steps per"
  echo "behavior, seeds: $SEEDS."
  echo
  echo "| seed | seekers | chasing emerged at (seeker steps) | tag rate, last 100 episodes | final seeker reward |"
  echo "|---|---|---|---|---|"
} > "$report"
for seed in $SEEDS; do
  train_run "$ROOT/configs/hide_and_seek.yaml" "rq3_no_penalty_s$seed" --seed "$seed" --max-steps "$STEPS"
  train_run "$ROOT/configs/hide_and_seek.yaml" "rq3_penalty_s$seed" --seed "$seed" --max-steps "$STEPS" \
    --param unseen_reward="$PENALTY"
  for arm in no_penalty penalty; do
    run_id=rq3_${arm}_s$seed
    episodes=$RESULTS/$run_id/metrics/episodes.csv
    rate=$(awk -F, -v c="$(column smoothed_tag_rate_running_and_chasing "$episodes")" \
      'NR > 1 { r = $c } END { printf "%.2f", r }' "$episodes")
    reward=$(awk -F, 'NR > 1 && $3 > 0 { r = $4 } END { printf "%.3f", r }' "$RESULTS/$run_id/metrics/Seeker.csv")
    echo "| $seed | $arm | $(emerged "$run_id" running_and_chasing) | $rate | $reward |" >> "$report"
  done
  plot "$REPORTS/rq3_s$seed" "rq3_no_penalty_s$seed" "rq3_penalty_s$seed"
  {
    echo
    echo "![tag rate over the last 100 episodes (rq3_penalty: unseen_reward $PENALTY), seed $seed](rq3_s$seed/strategies.png)"
    echo "![rewards, seed $seed](rq3_s$seed/reward.png)"
  } >> "$report"
done
echo "wrote $report"
