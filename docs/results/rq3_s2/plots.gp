# Learning curves written by `rlt plot`; run again with: gnuplot plots.gp (in this folder)
set grid lc rgb '#dddddd'
set format x '%.1s%c'
set key outside right top

set terminal pngcairo size 1000,420 font ',10' noenhanced
set output 'reward.png'
set yrange [*:*]
set title 'Cumulative reward (mean per episode)'
set xlabel 'steps of the behavior'
set ylabel 'reward'
plot 'data/reward.dat' index 0 using 1:2 with lines lw 1 lc rgb '#b01f77b4' notitle, \
     'data/reward.dat' index 0 using 1:3 with lines lw 2 lc rgb '#1f77b4' title 'rq3_no_penalty_s2 Hider', \
     'data/reward.dat' index 1 using 1:2 with lines lw 1 lc rgb '#b0d62728' notitle, \
     'data/reward.dat' index 1 using 1:3 with lines lw 2 lc rgb '#d62728' title 'rq3_no_penalty_s2 Seeker', \
     'data/reward.dat' index 2 using 1:2 with lines lw 1 lc rgb '#b02ca02c' notitle, \
     'data/reward.dat' index 2 using 1:3 with lines lw 2 lc rgb '#2ca02c' title 'rq3_penalty_s2 Hider', \
     'data/reward.dat' index 3 using 1:2 with lines lw 1 lc rgb '#b0ff7f0e' notitle, \
     'data/reward.dat' index 3 using 1:3 with lines lw 2 lc rgb '#ff7f0e' title 'rq3_penalty_s2 Seeker'
set output

set terminal pngcairo size 1000,420 font ',10' noenhanced
set output 'episode_length.png'
set yrange [*:*]
set title 'Episode length (mean)'
set xlabel 'steps of the behavior'
set ylabel 'decisions'
plot 'data/episode_length.dat' index 0 using 1:2 with lines lw 1 lc rgb '#b01f77b4' notitle, \
     'data/episode_length.dat' index 0 using 1:3 with lines lw 2 lc rgb '#1f77b4' title 'rq3_no_penalty_s2 Hider', \
     'data/episode_length.dat' index 1 using 1:2 with lines lw 1 lc rgb '#b0d62728' notitle, \
     'data/episode_length.dat' index 1 using 1:3 with lines lw 2 lc rgb '#d62728' title 'rq3_no_penalty_s2 Seeker', \
     'data/episode_length.dat' index 2 using 1:2 with lines lw 1 lc rgb '#b02ca02c' notitle, \
     'data/episode_length.dat' index 2 using 1:3 with lines lw 2 lc rgb '#2ca02c' title 'rq3_penalty_s2 Hider', \
     'data/episode_length.dat' index 3 using 1:2 with lines lw 1 lc rgb '#b0ff7f0e' notitle, \
     'data/episode_length.dat' index 3 using 1:3 with lines lw 2 lc rgb '#ff7f0e' title 'rq3_penalty_s2 Seeker'
set output

set terminal pngcairo size 1400,800 font ',10' noenhanced
set output 'losses.png'
set multiplot layout 2,2
set yrange [*:*]
set title 'Policy loss'
set xlabel 'steps of the behavior'
set ylabel 'loss'
plot 'data/losses.dat' index 0 using 1:2 with lines lw 1 lc rgb '#b01f77b4' notitle, \
     'data/losses.dat' index 0 using 1:3 with lines lw 2 lc rgb '#1f77b4' title 'rq3_no_penalty_s2 Hider', \
     'data/losses.dat' index 1 using 1:2 with lines lw 1 lc rgb '#b0d62728' notitle, \
     'data/losses.dat' index 1 using 1:3 with lines lw 2 lc rgb '#d62728' title 'rq3_no_penalty_s2 Seeker', \
     'data/losses.dat' index 2 using 1:2 with lines lw 1 lc rgb '#b02ca02c' notitle, \
     'data/losses.dat' index 2 using 1:3 with lines lw 2 lc rgb '#2ca02c' title 'rq3_penalty_s2 Hider', \
     'data/losses.dat' index 3 using 1:2 with lines lw 1 lc rgb '#b0ff7f0e' notitle, \
     'data/losses.dat' index 3 using 1:3 with lines lw 2 lc rgb '#ff7f0e' title 'rq3_penalty_s2 Seeker'
set yrange [*:*]
set title 'Value loss'
set xlabel 'steps of the behavior'
set ylabel 'loss'
plot 'data/losses.dat' index 4 using 1:2 with lines lw 1 lc rgb '#b01f77b4' notitle, \
     'data/losses.dat' index 4 using 1:3 with lines lw 2 lc rgb '#1f77b4' title 'rq3_no_penalty_s2 Hider', \
     'data/losses.dat' index 5 using 1:2 with lines lw 1 lc rgb '#b0d62728' notitle, \
     'data/losses.dat' index 5 using 1:3 with lines lw 2 lc rgb '#d62728' title 'rq3_no_penalty_s2 Seeker', \
     'data/losses.dat' index 6 using 1:2 with lines lw 1 lc rgb '#b02ca02c' notitle, \
     'data/losses.dat' index 6 using 1:3 with lines lw 2 lc rgb '#2ca02c' title 'rq3_penalty_s2 Hider', \
     'data/losses.dat' index 7 using 1:2 with lines lw 1 lc rgb '#b0ff7f0e' notitle, \
     'data/losses.dat' index 7 using 1:3 with lines lw 2 lc rgb '#ff7f0e' title 'rq3_penalty_s2 Seeker'
set yrange [*:*]
set title 'Baseline loss (MA-POCA)'
set xlabel 'steps of the behavior'
set ylabel 'loss'
plot 'data/losses.dat' index 8 using 1:2 with lines lw 1 lc rgb '#b0d62728' notitle, \
     'data/losses.dat' index 8 using 1:3 with lines lw 2 lc rgb '#d62728' title 'rq3_no_penalty_s2 Seeker', \
     'data/losses.dat' index 9 using 1:2 with lines lw 1 lc rgb '#b0ff7f0e' notitle, \
     'data/losses.dat' index 9 using 1:3 with lines lw 2 lc rgb '#ff7f0e' title 'rq3_penalty_s2 Seeker'
unset multiplot
set output

set terminal pngcairo size 1400,420 font ',10' noenhanced
set output 'policy.png'
set multiplot layout 1,2
set yrange [*:*]
set title 'Policy entropy'
set xlabel 'steps of the behavior'
set ylabel 'entropy'
plot 'data/policy.dat' index 0 using 1:2 with lines lw 1 lc rgb '#b01f77b4' notitle, \
     'data/policy.dat' index 0 using 1:3 with lines lw 2 lc rgb '#1f77b4' title 'rq3_no_penalty_s2 Hider', \
     'data/policy.dat' index 1 using 1:2 with lines lw 1 lc rgb '#b0d62728' notitle, \
     'data/policy.dat' index 1 using 1:3 with lines lw 2 lc rgb '#d62728' title 'rq3_no_penalty_s2 Seeker', \
     'data/policy.dat' index 2 using 1:2 with lines lw 1 lc rgb '#b02ca02c' notitle, \
     'data/policy.dat' index 2 using 1:3 with lines lw 2 lc rgb '#2ca02c' title 'rq3_penalty_s2 Hider', \
     'data/policy.dat' index 3 using 1:2 with lines lw 1 lc rgb '#b0ff7f0e' notitle, \
     'data/policy.dat' index 3 using 1:3 with lines lw 2 lc rgb '#ff7f0e' title 'rq3_penalty_s2 Seeker'
set yrange [0.00015:0.00045]
set title 'Learning rate'
set xlabel 'steps of the behavior'
set ylabel 'learning rate'
plot 'data/policy.dat' index 4 using 1:2 with lines lw 1 lc rgb '#b01f77b4' notitle, \
     'data/policy.dat' index 4 using 1:3 with lines lw 2 lc rgb '#1f77b4' title 'rq3_no_penalty_s2 Hider', \
     'data/policy.dat' index 5 using 1:2 with lines lw 1 lc rgb '#b0d62728' notitle, \
     'data/policy.dat' index 5 using 1:3 with lines lw 2 lc rgb '#d62728' title 'rq3_no_penalty_s2 Seeker', \
     'data/policy.dat' index 6 using 1:2 with lines lw 1 lc rgb '#b02ca02c' notitle, \
     'data/policy.dat' index 6 using 1:3 with lines lw 2 lc rgb '#2ca02c' title 'rq3_penalty_s2 Hider', \
     'data/policy.dat' index 7 using 1:2 with lines lw 1 lc rgb '#b0ff7f0e' notitle, \
     'data/policy.dat' index 7 using 1:3 with lines lw 2 lc rgb '#ff7f0e' title 'rq3_penalty_s2 Seeker'
unset multiplot
set output

set terminal pngcairo size 1000,420 font ',10' noenhanced
set output 'elo.png'
set yrange [*:*]
set title 'Self-play ELO'
set xlabel 'steps of the behavior'
set ylabel 'ELO'
plot 'data/elo.dat' index 0 using 1:2 with lines lw 1 lc rgb '#b01f77b4' notitle, \
     'data/elo.dat' index 0 using 1:3 with lines lw 2 lc rgb '#1f77b4' title 'rq3_no_penalty_s2 Hider', \
     'data/elo.dat' index 1 using 1:2 with lines lw 1 lc rgb '#b0d62728' notitle, \
     'data/elo.dat' index 1 using 1:3 with lines lw 2 lc rgb '#d62728' title 'rq3_no_penalty_s2 Seeker', \
     'data/elo.dat' index 2 using 1:2 with lines lw 1 lc rgb '#b02ca02c' notitle, \
     'data/elo.dat' index 2 using 1:3 with lines lw 2 lc rgb '#2ca02c' title 'rq3_penalty_s2 Hider', \
     'data/elo.dat' index 3 using 1:2 with lines lw 1 lc rgb '#b0ff7f0e' notitle, \
     'data/elo.dat' index 3 using 1:3 with lines lw 2 lc rgb '#ff7f0e' title 'rq3_penalty_s2 Seeker'
set output

set terminal pngcairo size 1000,420 font ',10' noenhanced
set output 'lessons.png'
set yrange [*:*]
set title 'Lesson of level'
set xlabel 'total steps'
set ylabel 'lesson'
plot 'data/lessons.dat' index 0 using 1:3 with steps lw 2 lc rgb '#1f77b4' title 'rq3_no_penalty_s2', \
     'data/lessons.dat' index 1 using 1:3 with steps lw 2 lc rgb '#2ca02c' title 'rq3_penalty_s2'
set output

set terminal pngcairo size 1400,420 font ',10' noenhanced
set output 'strategies.png'
set multiplot layout 1,2
set yrange [*:*]
set title 'running_and_chasing: tag_rate over the last episodes'
set xlabel 'Seeker steps'
set ylabel 'tag_rate'
plot 'data/strategies.dat' index 0 using 1:3 with lines lw 2 lc rgb '#d62728' title 'rq3_no_penalty_s2 Seeker', \
     'data/strategies.dat' index 1 using 1:3 with lines lw 2 lc rgb '#ff7f0e' title 'rq3_penalty_s2 Seeker'
set yrange [0:1]
set title 'shelter: fort_rate over the last episodes'
set xlabel 'Hider steps'
set ylabel 'fort_rate'
plot 'data/strategies.dat' index 2 using 1:3 with lines lw 2 lc rgb '#1f77b4' title 'rq3_no_penalty_s2 Hider', \
     'data/strategies.dat' index 3 using 1:3 with lines lw 2 lc rgb '#2ca02c' title 'rq3_penalty_s2 Hider'
unset multiplot
set output

set terminal pngcairo size 1400,1560 font ',10' noenhanced
set output 'episode_metrics.png'
set multiplot layout 4,2
set yrange [*:*]
set title 'fort_rate'
set xlabel 'total steps'
set ylabel 'fort_rate'
plot 'data/episode_metrics.dat' index 0 using 1:2 with lines lw 1 lc rgb '#b01f77b4' notitle, \
     'data/episode_metrics.dat' index 0 using 1:3 with lines lw 2 lc rgb '#1f77b4' title 'rq3_no_penalty_s2', \
     'data/episode_metrics.dat' index 1 using 1:2 with lines lw 1 lc rgb '#b02ca02c' notitle, \
     'data/episode_metrics.dat' index 1 using 1:3 with lines lw 2 lc rgb '#2ca02c' title 'rq3_penalty_s2'
set yrange [*:*]
set title 'hidden_fraction'
set xlabel 'total steps'
set ylabel 'hidden_fraction'
plot 'data/episode_metrics.dat' index 2 using 1:2 with lines lw 1 lc rgb '#b01f77b4' notitle, \
     'data/episode_metrics.dat' index 2 using 1:3 with lines lw 2 lc rgb '#1f77b4' title 'rq3_no_penalty_s2', \
     'data/episode_metrics.dat' index 3 using 1:2 with lines lw 1 lc rgb '#b02ca02c' notitle, \
     'data/episode_metrics.dat' index 3 using 1:3 with lines lw 2 lc rgb '#2ca02c' title 'rq3_penalty_s2'
set yrange [*:*]
set title 'openings_closed'
set xlabel 'total steps'
set ylabel 'openings_closed'
plot 'data/episode_metrics.dat' index 4 using 1:2 with lines lw 1 lc rgb '#b01f77b4' notitle, \
     'data/episode_metrics.dat' index 4 using 1:3 with lines lw 2 lc rgb '#1f77b4' title 'rq3_no_penalty_s2', \
     'data/episode_metrics.dat' index 5 using 1:2 with lines lw 1 lc rgb '#b02ca02c' notitle, \
     'data/episode_metrics.dat' index 5 using 1:3 with lines lw 2 lc rgb '#2ca02c' title 'rq3_penalty_s2'
set yrange [*:*]
set title 'prop_start_offset'
set xlabel 'total steps'
set ylabel 'prop_start_offset'
plot 'data/episode_metrics.dat' index 6 using 1:2 with lines lw 1 lc rgb '#b01f77b4' notitle, \
     'data/episode_metrics.dat' index 6 using 1:3 with lines lw 2 lc rgb '#1f77b4' title 'rq3_no_penalty_s2', \
     'data/episode_metrics.dat' index 7 using 1:2 with lines lw 1 lc rgb '#b02ca02c' notitle, \
     'data/episode_metrics.dat' index 7 using 1:3 with lines lw 2 lc rgb '#2ca02c' title 'rq3_penalty_s2'
set yrange [*:*]
set title 'seen_fraction'
set xlabel 'total steps'
set ylabel 'seen_fraction'
plot 'data/episode_metrics.dat' index 8 using 1:2 with lines lw 1 lc rgb '#b01f77b4' notitle, \
     'data/episode_metrics.dat' index 8 using 1:3 with lines lw 2 lc rgb '#1f77b4' title 'rq3_no_penalty_s2', \
     'data/episode_metrics.dat' index 9 using 1:2 with lines lw 1 lc rgb '#b02ca02c' notitle, \
     'data/episode_metrics.dat' index 9 using 1:3 with lines lw 2 lc rgb '#2ca02c' title 'rq3_penalty_s2'
set yrange [*:*]
set title 'tag_rate'
set xlabel 'total steps'
set ylabel 'tag_rate'
plot 'data/episode_metrics.dat' index 10 using 1:2 with lines lw 1 lc rgb '#b01f77b4' notitle, \
     'data/episode_metrics.dat' index 10 using 1:3 with lines lw 2 lc rgb '#1f77b4' title 'rq3_no_penalty_s2', \
     'data/episode_metrics.dat' index 11 using 1:2 with lines lw 1 lc rgb '#b02ca02c' notitle, \
     'data/episode_metrics.dat' index 11 using 1:3 with lines lw 2 lc rgb '#2ca02c' title 'rq3_penalty_s2'
set yrange [*:*]
set title 'tagged'
set xlabel 'total steps'
set ylabel 'tagged'
plot 'data/episode_metrics.dat' index 12 using 1:2 with lines lw 1 lc rgb '#b01f77b4' notitle, \
     'data/episode_metrics.dat' index 12 using 1:3 with lines lw 2 lc rgb '#1f77b4' title 'rq3_no_penalty_s2', \
     'data/episode_metrics.dat' index 13 using 1:2 with lines lw 1 lc rgb '#b02ca02c' notitle, \
     'data/episode_metrics.dat' index 13 using 1:3 with lines lw 2 lc rgb '#2ca02c' title 'rq3_penalty_s2'
unset multiplot
set output
