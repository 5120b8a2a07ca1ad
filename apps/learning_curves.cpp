#include "apps/learning_curves.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>

#include "rl/core/csv_line.h"
#include "rl/trainer/run_folder.h"

namespace fs = std::filesystem;

namespace rlt {

int CsvTable::column(const std::string& name) const {
  auto it = std::find(columns.begin(), columns.end(), name);
  return it == columns.end() ? -1 : int(it - columns.begin());
}

namespace {

double parse_cell(const std::string& cell) {
  const char* begin = cell.c_str();
  char* end = nullptr;
  const double v = std::strtod(begin, &end);
  if (end == begin || *end != '\0') return std::numeric_limits<double>::quiet_NaN();
  return v;
}

}  // namespace

CsvTable read_csv_table(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot read " + path);
  CsvTable table;
  std::string line;
  if (!std::getline(in, line) || line.empty())
    throw std::runtime_error(path + " has no header row");
  table.columns = split_csv_line(line);
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    const auto cells = split_csv_line(line);
    // a row shorter than the header (a column added since) has NaN in the missing cells
    std::vector<double> row(table.columns.size(), std::numeric_limits<double>::quiet_NaN());
    for (size_t i = 0; i < std::min(cells.size(), row.size()); ++i) row[i] = parse_cell(cells[i]);
    table.rows.push_back(std::move(row));
  }
  return table;
}

RunFolder run_folder_at(const std::string& dir) {
  fs::path folder = fs::absolute(dir).lexically_normal();
  if (!folder.has_filename()) folder = folder.parent_path();  // "results/run/"
  return RunFolder(folder.parent_path().string(), folder.filename().string());
}

RunCurves read_run_curves(const std::string& dir, const std::string& label) {
  const fs::path metrics = fs::path(dir) / "metrics";
  if (!fs::is_directory(dir)) throw std::runtime_error(dir + " is not a folder");
  if (!fs::is_directory(metrics))
    throw std::runtime_error(dir +
                             " has no metrics/ folder: not a run folder written by rlt train");
  RunCurves run;
  run.label = label;
  std::vector<std::string> files;
  for (const auto& entry : fs::directory_iterator(metrics))
    if (entry.path().extension() == ".csv" && entry.path().filename() != "episodes.csv")
      files.push_back(entry.path().string());
  std::sort(files.begin(), files.end());
  if (files.empty()) throw std::runtime_error(metrics.string() + " has no <Behavior>.csv file");
  for (const auto& f : files) {
    run.behaviors.push_back(fs::path(f).stem().string());
    run.updates.push_back(read_csv_table(f));
  }
  if (fs::exists(metrics / "episodes.csv"))
    run.episodes = read_csv_table((metrics / "episodes.csv").string());
  const RunFolder run_folder = run_folder_at(dir);
  if (fs::exists(run_folder.status_path()))
    for (const auto& e : run_folder.read_status().strategies)
      run.strategies.push_back({e.strategy, e.metric, e.behavior});
  return run;
}

std::vector<double> smooth_like_tensorboard(const std::vector<double>& y, double weight) {
  std::vector<double> out(y.size());
  double average = 0, scale = 0;
  for (size_t i = 0; i < y.size(); ++i) {
    average = weight * average + (1 - weight) * y[i];
    scale = weight * scale + (1 - weight);
    out[i] = average / scale;
  }
  return out;
}

namespace {

// the finite points of columns `x` and `y` of `table`, or an empty series when either is absent
Series series_of(const CsvTable& table, const std::string& x, const std::string& y,
                 const std::string& title, int colour) {
  Series s;
  s.title = title;
  s.colour = colour;
  const int xi = table.column(x), yi = table.column(y);
  if (xi < 0 || yi < 0) return s;
  for (const auto& row : table.rows)
    if (std::isfinite(row[xi]) && std::isfinite(row[yi])) {
      s.x.push_back(row[xi]);
      s.y.push_back(row[yi]);
    }
  return s;
}

bool all_zero(const Series& s) {
  return std::all_of(s.y.begin(), s.y.end(), [](double v) { return v == 0; });
}

}  // namespace

bool is_episode_metric(const std::string& column, const RunCurves& run) {
  if (column == "total_steps" || column == "elapsed_s" || column == "episodes") return false;
  if (column.rfind("lesson_", 0) == 0 || column.rfind("smoothed_", 0) == 0) return false;
  for (const auto& b : run.behaviors)
    if (column == b + "_step") return false;
  return true;
}

std::vector<Figure> learning_curve_figures(const std::vector<RunCurves>& runs, double smoothing) {
  if (smoothing < 0 || smoothing >= 1) throw std::invalid_argument("smoothing must be in [0, 1)");
  const bool several = runs.size() > 1;
  // a colour per run and behavior, in order
  std::map<std::pair<size_t, std::string>, int> colours;
  for (size_t r = 0; r < runs.size(); ++r)
    for (const auto& b : runs[r].behaviors)
      colours.emplace(std::make_pair(r, b), int(colours.size()));
  auto behavior_title = [&](size_t r, const std::string& b) {
    return several ? runs[r].label + " " + b : b;
  };

  std::vector<Figure> figures;
  // per-behavior columns of metrics/<Behavior>.csv, against the behavior's steps
  auto update_panel = [&](const std::string& column, const std::string& title,
                          const std::string& y_label, bool skip_zero) {
    Panel p{title, "steps of the behavior", y_label, {}};
    for (size_t r = 0; r < runs.size(); ++r)
      for (size_t b = 0; b < runs[r].behaviors.size(); ++b) {
        const std::string& name = runs[r].behaviors[b];
        Series s = series_of(runs[r].updates[b], "step", column, behavior_title(r, name),
                             colours.at({r, name}));
        if (!s.x.empty() && !(skip_zero && all_zero(s))) p.series.push_back(std::move(s));
      }
    return p;
  };
  figures.push_back(
      {"reward",
       {update_panel("mean_return", "Cumulative reward (mean per episode)", "reward", false)}});
  figures.push_back({"episode_length",
                     {update_panel("mean_length", "Episode length (mean)", "decisions", false)}});
  figures.push_back({"losses",
                     {update_panel("policy_loss", "Policy loss", "loss", false),
                      update_panel("value_loss", "Value loss", "loss", false),
                      update_panel("baseline_loss", "Baseline loss (MA-POCA)", "loss", true)}});
  figures.push_back({"policy",
                     {update_panel("entropy", "Policy entropy", "entropy", false),
                      update_panel("learning_rate", "Learning rate", "learning rate", false),
                      update_panel("approx_kl", "Approximate KL from the collecting policy",
                                   "KL", false),
                      update_panel("clip_fraction", "Clip fraction", "share of rows", false)}});
  figures.push_back({"elo", {update_panel("elo", "Self-play ELO", "ELO", false)}});

  // run-wide columns of metrics/episodes.csv
  Figure lessons{"lessons", {}}, strategies{"strategies", {}}, metrics{"episode_metrics", {}};
  std::map<std::string, size_t> lesson_panel, metric_panel, strategy_panel;
  for (size_t r = 0; r < runs.size(); ++r) {
    const CsvTable& table = runs[r].episodes;
    const int run_colour = colours.at({r, runs[r].behaviors.front()});
    for (const auto& column : table.columns) {
      const bool lesson = column.rfind("lesson_", 0) == 0;
      if (!lesson && !is_episode_metric(column, runs[r])) continue;
      Figure& figure = lesson ? lessons : metrics;
      auto& index = lesson ? lesson_panel : metric_panel;
      const std::string name = lesson ? column.substr(7) : column;
      if (!index.count(name)) {
        index[name] = figure.panels.size();
        figure.panels.push_back(
            {lesson ? "Lesson of " + name : name, "total steps", lesson ? "lesson" : name, {}});
      }
      Series s =
          series_of(table, "total_steps", column, several ? runs[r].label : name, run_colour);
      if (!s.x.empty()) figure.panels[index[name]].series.push_back(std::move(s));
    }
    for (const auto& st : runs[r].strategies) {
      const std::string column = "smoothed_" + st.metric + "_" + st.name;
      if (!strategy_panel.count(st.name)) {
        strategy_panel[st.name] = strategies.panels.size();
        strategies.panels.push_back({st.name + ": " + st.metric + " over the last episodes",
                                     st.behavior + " steps",
                                     st.metric,
                                     {}});
      }
      Panel& panel = strategies.panels[strategy_panel[st.name]];
      const auto colour = colours.find({r, st.behavior});
      Series s = series_of(table, st.behavior + "_step", column, behavior_title(r, st.behavior),
                           colour == colours.end() ? run_colour : colour->second);
      if (!s.x.empty()) panel.series.push_back(std::move(s));
    }
  }
  figures.push_back(std::move(lessons));
  figures.push_back(std::move(strategies));
  figures.push_back(std::move(metrics));

  // smoothing (not of lessons, which are steps, nor of strategy rates, smoothed already)
  for (auto& figure : figures)
    for (auto& panel : figure.panels)
      for (auto& s : panel.series)
        s.smoothed = figure.name == "lessons" || figure.name == "strategies"
                         ? s.y
                         : smooth_like_tensorboard(s.y, smoothing);
  // what has nothing to draw is left out
  for (auto& figure : figures)
    figure.panels.erase(std::remove_if(figure.panels.begin(), figure.panels.end(),
                                       [](const Panel& p) { return p.series.empty(); }),
                        figure.panels.end());
  figures.erase(std::remove_if(figures.begin(), figures.end(),
                               [](const Figure& f) { return f.panels.empty(); }),
                figures.end());
  return figures;
}

}  // namespace rlt
