// Where a training run spent its curriculum: for each lesson of one curriculum parameter, when the
// run entered it, how many steps it spent there, and the env's episode metrics averaged over the
// episodes played in it (what `rlt lessons` prints). Read from metrics/episodes.csv, whose rows are
// one per summary: a lesson's figures are those of the rows logged while it was current, so a
// lesson change is placed to within one summary and a lesson passed between two summaries has none.
#pragma once

#include <string>
#include <vector>

#include "apps/learning_curves.h"

namespace rlt {

struct LessonSummary {
  int lesson = 0;       // the lesson's index in the curriculum
  std::string name;     // its name in the run's configuration ("" when unknown)
  double entered = 0;   // the step (of the table's counter) at the summary before its first row
  double steps = 0;     // the counter's steps over the rows logged in the lesson
  int visits = 0;       // separate stretches of rows (more than one after a fallback)
  double episodes = 0;  // episodes of the counted rows
  std::vector<double> means;  // [metrics] episode-weighted means over the counted rows; NaN: none
};

struct LessonTable {
  std::string parameter;             // the curriculum parameter (episodes.csv's lesson_<parameter>)
  std::string behavior;              // whose turns count and whose steps; "" for every row, total
  std::vector<std::string> metrics;  // the episode metrics averaged
  std::vector<LessonSummary> lessons;  // in the order the run first entered them
};

// The lessons of `parameter` in `run` (read_run_curves; `lesson_names` from its configuration,
// indexed by lesson, may be empty). With `behavior`, steps are that behavior's and only the rows in
// which its steps alone advanced count for episodes and metrics (its turns in self-play). `metrics`
// empty: every episode metric of the file. Throws naming the problem when the run has no
// episodes.csv, the parameter, behavior or a metric is not in it.
LessonTable summarize_lessons(const RunCurves& run, const std::string& parameter,
                              const std::string& behavior, std::vector<std::string> metrics,
                              const std::vector<std::string>& lesson_names);

// The curriculum parameters of `run`'s episodes.csv (its lesson_<name> columns), sorted.
std::vector<std::string> curriculum_parameters(const RunCurves& run);

// The table as Markdown (steps as integers, metrics with `decimals` decimals) and as one JSON object.
std::string lesson_table_markdown(const LessonTable& table, int decimals);
std::string lesson_table_json(const LessonTable& table);

}  // namespace rlt
