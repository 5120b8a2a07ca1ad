#!/usr/bin/env bash
# RQ1: does the curriculum help the hiders? The default configuration (four levels advanced by the
# hiders' reward) against the same configuration at level 4 from the first step, 3.3M steps per
# behavior each, for every seed in SEEDS (default 1). Writes docs/results/rq1_curriculum.md and
# its plots. Not run in CI: each run takes tens of minutes on 2 cores.
source "$(dirname "$0")/common.sh"
ensure_built
ensure_gnuplot
STEPS=${STEPS:-3300000}
report=$REPORTS/rq1_curriculum.md
{
  echo "# RQ1: curriculum vs no curriculum for the hiders"
  echo
  echo "Produced by \`scripts/experiments/rq1_curriculum.sh\` on $(date -u +%Y-%m-%d), $STEPS steps"
  echo "per behavior, seeds: $SEEDS. Curriculum: \`configs/hide_and_seek.yaml\`; no curriculum:"
  echo "\`configs/experiments/rq1_no_curriculum.yaml\` (the default with its curriculum frozen at the"
  echo "last lesson: level 4 throughout). The curriculum's lessons 0-5 are level 1 (the prop moving from"
  echo "its doorway half way to its own place), 6-17 level 2 (two props, from their doorways to their"
  echo "own places), 18 level 3 and 19 level 4."
  echo
  echo "| seed | arm | final hider reward | final lesson (index) | fort rate (last row) | minutes |"
  echo "|---|---|---|---|---|---|"
} > "$report"
for seed in $SEEDS; do
  train_run "$ROOT/configs/hide_and_seek.yaml" "rq1_curriculum_s$seed" --seed "$seed" --max-steps "$STEPS"
  train_run "$ROOT/configs/experiments/rq1_no_curriculum.yaml" "rq1_no_curriculum_s$seed" --seed "$seed" --max-steps "$STEPS"
  for arm in curriculum no_curriculum; do
    run=$RESULTS/rq1_${arm}_s$seed
    hider=$run/metrics/Hider.csv
    episodes=$run/metrics/episodes.csv
    reward=$(awk -F, 'NR > 1 && $3 > 0 { r = $4 } END { printf "%.3f", r }' "$hider")
    # the lesson index in the level curriculum; the control arm has no curriculum
    lesson=$({ grep -o '"level": [0-9]*' "$run/training_status.json" || true; } | awk '{ print $2 }')
    fort=$(awk -F, -v c="$(column fort_rate "$episodes")" 'NR > 1 { f = $c } END { printf "%.2f", f }' "$episodes")
    minutes=$(awk -F, 'END { printf "%.0f", $2 / 60 }' "$hider")
    echo "| $seed | $arm | $reward | ${lesson:-fixed 4} | $fort | $minutes |" >> "$report"
  done
  plot "$REPORTS/rq1_s$seed" "rq1_curriculum_s$seed" "rq1_no_curriculum_s$seed"
  {
    echo
    echo "![rewards, seed $seed](rq1_s$seed/reward.png)"
    echo "![lessons, seed $seed](rq1_s$seed/lessons.png)"
    echo "![episode metrics (fort rate among them), seed $seed](rq1_s$seed/episode_metrics.png)"
  } >> "$report"
done
echo "wrote $report"
