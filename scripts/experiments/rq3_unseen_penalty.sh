#!/usr/bin/env bash
# RQ3: do penalties slow learning? Seekers with a constant penalty per test-phase frame in which no
# hider is seen (--param unseen_reward=PENALTY, default -0.001) against the default configuration
# (no penalty), STEPS per behavior (default 1.6M, the paper's chasing figure), seeds in SEEDS.
# Writes docs/results/rq3_unseen_penalty.md. Compares the seekers' tag rate, not their reward
# (the penalty changes the reward's scale): when chasing emerged, the rate over the last 100
# episodes when the seekers stopped learning (later rows are the hiders' turns), and both arms'
# final seekers against the same hiders (EVAL_EPISODES, default 32, each) where the seekers
# learned: level 1, half the hiders just outside the room.
source "$(dirname "$0")/common.sh"
ensure_built
ensure_gnuplot
STEPS=${STEPS:-1600000}
PENALTY=${PENALTY:--0.001}
EVAL_EPISODES=${EVAL_EPISODES:-32}
report=$REPORTS/rq3_unseen_penalty.md
{
  echo "# RQ3: a constant penalty for seekers while no hider is seen"
  echo
  echo "Produced by \`scripts/experiments/rq3_unseen_penalty.sh\` on $(date -u +%Y-%m-%d): the"
  echo "default configuration with and without \`--param unseen_reward=$PENALTY\`, $STEPS steps per"
  echo "behavior, seeds: $SEEDS."
  echo
  echo "| seed | seekers | chasing emerged at (seeker steps) | tag rate when they stopped | seeker reward, last 10 updates |"
  echo "|---|---|---|---|---|"
} > "$report"
for seed in $SEEDS; do
  train_run "$ROOT/configs/hide_and_seek.yaml" "rq3_no_penalty_s$seed" --seed "$seed" --max-steps "$STEPS"
  train_run "$ROOT/configs/hide_and_seek.yaml" "rq3_penalty_s$seed" --seed "$seed" --max-steps "$STEPS" \
    --param unseen_reward="$PENALTY"
  for arm in no_penalty penalty; do
    run_id=rq3_${arm}_s$seed
    episodes=$RESULTS/$run_id/metrics/episodes.csv
    # the first row at the seekers' last step: the rate over their last 100 learning episodes
    rate=$(awk -F, -v s="$(column Seeker_step "$episodes")" -v steps="$STEPS" \
      -v c="$(column smoothed_tag_rate_running_and_chasing "$episodes")" \
      'NR > 1 && $s >= steps && !done { printf "%.2f", $c; done = 1 }' "$episodes")
    reward=$(recent_return "$RESULTS/$run_id/metrics/Seeker.csv")
    echo "| $seed | $arm | $(emerged "$run_id" running_and_chasing) | $rate | $reward |" >> "$report"
  done
done
# then, per seed, the evaluations and the plots (after the whole table)
for seed in $SEEDS; do
  {
    echo
    echo "Seed $seed, the final seekers against the same hiders ($EVAL_EPISODES episodes each, \`rlt eval RUN"
    echo "--policy Hider=WHO --param level=1 --param prop_start_offset=0.5 --param hider_outside_chance=0.5\`):"
    echo
    echo "| seekers | hiders | tag rate | seen fraction |"
    echo "|---|---|---|---|"
  } >> "$report"
  for arm in no_penalty penalty; do
    for hiders in still scripted no_penalty penalty; do
      who=$hiders
      [ "$hiders" = still ] || [ "$hiders" = scripted ] || who=$RESULTS/rq3_${hiders}_s$seed
      line=$("$RLT" eval "$RESULTS/rq3_${arm}_s$seed" --policy Hider="$who" --param level=1 \
        --param prop_start_offset=0.5 --param hider_outside_chance=0.5 --episodes "$EVAL_EPISODES" \
        --json | grep '"behavior":"Seeker"')
      echo "| $arm | $hiders | $(json_number "$line" tag_rate) | $(json_number "$line" seen_fraction) |" \
        >> "$report"
    done
  done
  plot "$REPORTS/rq3_s$seed" "rq3_no_penalty_s$seed" "rq3_penalty_s$seed"
  {
    echo
    echo "![tag rate over the last 100 episodes (rq3_penalty: unseen_reward $PENALTY; the drops are the hiders' turns, dated at the seekers' last step), seed $seed](rq3_s$seed/strategies.png)"
    echo "![rewards, seed $seed](rq3_s$seed/reward.png)"
  } >> "$report"
done
echo "wrote $report"
