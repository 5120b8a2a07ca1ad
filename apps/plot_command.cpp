// rlt plot: PNG learning curves of one run or several side by side.
#include <filesystem>
#include <iostream>
#include <set>
#include <string>
#include <vector>

#include "apps/command_line.h"
#include "apps/commands.h"
#include "apps/gnuplot_figures.h"
#include "apps/learning_curves.h"

namespace fs = std::filesystem;

namespace rlt {

const char* const kPlotHelp = R"(Usage: rlt plot RUN_DIR [RUN_DIR...] [options]

Draws the learning curves of training runs as PNG files with gnuplot (Debian: gnuplot-nox), one
line per run and behavior: reward.png, episode_length.png, losses.png (policy, value, MA-POCA
baseline), policy.png (entropy, learning rate, approximate KL and clip fraction per update),
elo.png (self-play), lessons.png (curricula), strategies.png (the env's strategy rates by the
steps of their behavior) and episode_metrics.png (the env's episode metrics). Figures with
nothing to draw are left out. Reads each run's metrics/ folder and training_status.json; works
while the run is still training.

Options:
  --out DIR        where the PNGs go (default: RUN_DIR/plots for one run, plots/ for several);
                   DIR/plots.gp and DIR/data/ hold the script and the points, to edit and redraw
  --smoothing W    TensorBoard's smoothing weight in [0, 1) (default 0.6; 0 draws the points only);
                   the points themselves are drawn faintly behind the smoothed line

Example:
  rlt plot results/hide_and_seek
  rlt plot results/seed1 results/seed2 --out docs/results/seeds
)";

int run_plot(const std::vector<std::string>& args) {
  CommandLine cl(args, {}, {"--out", "--smoothing"});
  const auto& dirs = cl.positional();
  if (dirs.empty()) throw UsageError("expected at least one RUN_DIR");
  const double smoothing = cl.number("--smoothing", 0.6, 0, 1);
  // runs are named by their folder, or by the path given when two folders share a name
  std::set<std::string> names, repeated;
  for (const auto& d : dirs) {
    const std::string name = fs::path(d).lexically_normal().filename().string();
    if (!names.insert(name).second) repeated.insert(name);
  }
  std::vector<RunCurves> runs;
  for (const auto& d : dirs) {
    const std::string name = fs::path(d).lexically_normal().filename().string();
    runs.push_back(read_run_curves(d, repeated.count(name) || name.empty() ? d : name));
  }
  const std::string out =
      cl.value("--out", dirs.size() == 1 ? (fs::path(dirs[0]) / "plots").string() : "plots");
  const auto figures = learning_curve_figures(runs, smoothing);
  if (figures.empty()) throw std::runtime_error("no metrics to plot yet (no update was logged)");
  const auto pngs = write_gnuplot_figures(figures, out, smoothing > 0);
  run_gnuplot(out);
  for (const auto& png : pngs) std::cout << png << "\n";
  return 0;
}

}  // namespace rlt
