#!/usr/bin/env bash
# RQ2: how many steps until running-and-chasing and until shelter emerge? Trains the default
# configuration (STEPS per behavior, default its own max_steps) for every seed in SEEDS and reads
# the emergence steps the run recorded (training_status.json: the first step where the rate over
# the last 100 episodes exceeds 0.5; shelter counts episodes at level 2 and above with the props
# starting at their own places). Writes
# docs/results/rq2_emergence.md with the paper's and OpenAI's figures next to ours, and the machine
# each run ran on (a seed's figures hold on one machine only).
source "$(dirname "$0")/common.sh"
ensure_built
ensure_gnuplot
STEPS=${STEPS:-}
report=$REPORTS/rq2_emergence.md
{
  echo "# RQ2: steps until the strategies emerge"
  echo
  echo "Produced by \`scripts/experiments/rq2_emergence.sh\` on $(date -u +%Y-%m-%d) from"
  echo "\`configs/hide_and_seek.yaml\`${STEPS:+ with --max-steps $STEPS}, seeds: $SEEDS, on $(nproc) cores."
  echo
  echo "| | running and chasing (seeker steps) | shelter (hider steps) | machine |"
  echo "|---|---|---|---|"
  echo "| paper (Unity ML-Agents) | 1.6M | 2.3M | |"
  echo "| OpenAI hide-and-seek | about 2M | about 25M | |"
} > "$report"
for seed in $SEEDS; do
  run_id=rq2_default_s$seed
  train_run "$ROOT/configs/hide_and_seek.yaml" "$run_id" --seed "$seed" ${STEPS:+--max-steps "$STEPS"}
  chase=$(emerged "$run_id" running_and_chasing)
  shelter=$(emerged "$run_id" shelter)
  chase_min=$(emerged_minutes "$run_id" running_and_chasing)
  shelter_min=$(emerged_minutes "$run_id" shelter)
  echo "| ours, seed $seed | $chase${chase_min:+ ($chase_min min)} | $shelter${shelter_min:+ ($shelter_min min)} | $(machines "$run_id") |" >> "$report"
  plot "$REPORTS/rq2_s$seed" "$run_id"
  {
    echo
    echo "![strategy rates (shelter: level >= 2, props at their places), seed $seed](rq2_s$seed/strategies.png)"
    echo "![lessons, seed $seed](rq2_s$seed/lessons.png)"
    echo "![episode metrics, seed $seed](rq2_s$seed/episode_metrics.png)"
  } >> "$report"
done
echo "wrote $report"
