// Draws learning-curve figures (learning_curves.h) as PNG files with gnuplot: the points go to
// OUT/data/<figure>.dat (one block per series: x, y, smoothed y), the drawing instructions to
// OUT/plots.gp, which gnuplot runs in OUT (so a user can edit it and run `gnuplot plots.gp` again).
#pragma once

#include <string>
#include <vector>

#include "apps/learning_curves.h"

namespace rlt {

// Writes the data files and plots.gp into `out_dir` (created if missing); returns the PNG paths
// the script will draw, one per figure.
std::vector<std::string> write_gnuplot_figures(const std::vector<Figure>& figures,
                                               const std::string& out_dir, bool draw_raw);

// Runs gnuplot on `out_dir`/plots.gp. Throws when gnuplot is not installed (naming the Debian
// package) or fails.
void run_gnuplot(const std::string& out_dir);

}  // namespace rlt
