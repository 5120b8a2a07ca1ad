#!/usr/bin/env bash
# RQ1: does the curriculum help the hiders? The default configuration (four levels advanced by the
# hiders' fort rate) against the same configuration at level 4 from the first step, 3.3M steps per
# behavior each, for every seed in SEEDS (default 1); then both arms' final hiders play
# EVAL_EPISODES (48) episodes at level 4 against scripted seekers and each arm's seekers. Writes
# docs/results/rq1_curriculum.md and its plots. Not run in CI: each run takes tens of minutes on
# 2 cores.
source "$(dirname "$0")/common.sh"
ensure_built
ensure_gnuplot
STEPS=${STEPS:-3300000}
EVAL_EPISODES=${EVAL_EPISODES:-48}
report=$REPORTS/rq1_curriculum.md

{
  echo "# RQ1: curriculum vs no curriculum for the hiders"
  echo
  echo "Produced by \`scripts/experiments/rq1_curriculum.sh\` on $(date -u +%Y-%m-%d), $STEPS steps"
  echo "per behavior, seeds: $SEEDS. Curriculum: \`configs/hide_and_seek.yaml\`; no curriculum:"
  echo "\`configs/experiments/rq1_no_curriculum.yaml\` (the default with its curriculum frozen at the"
  echo "last lesson: level 4 throughout). Lesson levelN_props_XXX is level N with the props starting"
  echo "XXX/100 of the way from their doorways to their own places."
  echo
  echo "| seed | arm | hider reward, last 10 updates | final lesson | fort rate, last 100 episodes | minutes |"
  echo "|---|---|---|---|---|---|"
} > "$report"
for seed in $SEEDS; do
  train_run "$ROOT/configs/hide_and_seek.yaml" "rq1_curriculum_s$seed" --seed "$seed" --max-steps "$STEPS"
  train_run "$ROOT/configs/experiments/rq1_no_curriculum.yaml" "rq1_no_curriculum_s$seed" --seed "$seed" --max-steps "$STEPS"
  for arm in curriculum no_curriculum; do
    run=$RESULTS/rq1_${arm}_s$seed
    hider=$run/metrics/Hider.csv
    episodes=$run/metrics/episodes.csv
    reward=$(recent_return "$hider")
    # the lesson reached in the level curriculum, by name (the control arm has no curriculum)
    lesson=$({ grep -o '"level": [0-9]*' "$run/training_status.json" || true; } | awk '{ print $2 }')
    [ -z "$lesson" ] ||
      lesson=$(grep -o 'name: level[^ ]*' "$run/configuration.yaml" | sed -n "$((lesson + 1))p" | cut -d' ' -f2)
    fort=$(tail -n 100 "$episodes" | awk -F, -v c="$(column fort_rate "$episodes")" \
      '{ f += $c } END { printf "%.2f", f / NR }')
    minutes=$(awk -F, 'END { printf "%.0f", $2 / 60 }' "$hider")
    echo "| $seed | $arm | $reward | ${lesson:-fixed 4} | $fort | $minutes |" >> "$report"
  done
done
# then, per seed, the evaluations and the plots (after the whole table)
for seed in $SEEDS; do
  # The rewards differ in kind between the arms (the curriculum's come from easier levels), so
  # both arms' final hiders also play level 4 against the same seekers.
  {
    echo
    echo "Seed $seed, the final hiders at level 4 ($EVAL_EPISODES episodes each, \`rlt eval RUN --param"
    echo "level=4 --policy Seeker=WHO\`):"
    echo
    echo "| hiders | seekers | fort rate | hidden fraction | tag rate |"
    echo "|---|---|---|---|---|"
  } >> "$report"
  for arm in curriculum no_curriculum; do
    for seekers in scripted curriculum no_curriculum; do
      who=$seekers
      [ "$seekers" = scripted ] || who=$RESULTS/rq1_${seekers}_s$seed
      line=$("$RLT" eval "$RESULTS/rq1_${arm}_s$seed" --param level=4 --policy Seeker="$who" \
        --episodes "$EVAL_EPISODES" --json | grep '"behavior":"Hider"')
      echo "| $arm | $seekers | $(json_number "$line" fort_rate) | $(json_number "$line" hidden_fraction)" \
        "| $(json_number "$line" tag_rate) |" >> "$report"
    done
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
