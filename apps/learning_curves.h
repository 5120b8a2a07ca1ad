// Learning curves of training runs, read from their metrics files (rl/trainer/run_folder.h):
// the figures `rlt plot` draws (reward, episode length, losses, entropy and learning rate, ELO,
// lessons, strategy rates, the env's episode metrics), each a set of panels whose series are one
// line per run and behavior. Nothing here draws; gnuplot_figures.h does.
#pragma once

#include <string>
#include <vector>

#include "rl/trainer/run_folder.h"

namespace rlt {

// A CSV file of numbers with a header row; cells that are empty or not numbers are NaN.
struct CsvTable {
  std::vector<std::string> columns;
  std::vector<std::vector<double>> rows;  // [rows][columns]

  int column(const std::string& name) const;  // -1 when absent
};

// Reads `path`; throws naming the file when it cannot be read or has no header.
CsvTable read_csv_table(const std::string& path);

// What `rlt plot` reads of one run folder.
struct RunCurves {
  std::string label;                   // how the run is named in the legends
  std::vector<std::string> behaviors;  // in the order of their metrics files' names
  std::vector<CsvTable> updates;       // metrics/<Behavior>.csv, one row per update
  CsvTable episodes;                   // metrics/episodes.csv (empty when the env has no metrics)
  struct Strategy {
    std::string name, metric, behavior;
  };
  std::vector<Strategy> strategies;  // from training_status.json
};

// The run folder at the path `dir` (a trailing slash allowed), for its files' names.
RunFolder run_folder_at(const std::string& dir);

// Reads the run folder `dir`; throws naming what is missing when it is not a run folder.
RunCurves read_run_curves(const std::string& dir, const std::string& label);

// Whether `column` of the run's episodes.csv is one of the env's episode metrics: not steps, time,
// the episode count, a lesson or a smoothed strategy rate.
bool is_episode_metric(const std::string& column, const RunCurves& run);

struct Series {
  std::string title;
  int colour = 0;                // the same run and behavior keep their colour in every figure
  std::vector<double> x, y;      // finite points only, in file order
  std::vector<double> smoothed;  // y smoothed like TensorBoard's slider (debiased moving average)
};

struct Panel {
  std::string title, x_label, y_label;
  std::vector<Series> series;
};

struct Figure {
  std::string name;  // file stem: reward, episode_length, losses, ...
  std::vector<Panel> panels;
};

// The figures for `runs` side by side. `smoothing` in [0, 1): 0 draws the points as they are.
// Figures and panels without a single finite point are left out.
std::vector<Figure> learning_curve_figures(const std::vector<RunCurves>& runs, double smoothing);

// TensorBoard's smoothing: an exponential moving average whose start is debiased, so the first
// points are not pulled towards zero.
std::vector<double> smooth_like_tensorboard(const std::vector<double>& y, double weight);

}  // namespace rlt
