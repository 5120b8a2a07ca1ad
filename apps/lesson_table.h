// Where a training run spent its curriculum: for each lesson of one curriculum parameter, when the
// run entered it, how many steps it spent there, and the env's episode metrics averaged over the
// episodes played in it (what `rlt lessons` prints). The metrics come from metrics/episodes.csv,
// whose rows are one per summary: a lesson's are those of the rows logged while it was current.
// The entries, steps and stretches come from metrics/lessons.csv (one row per change, at its
// steps) when the run has it; runs trained before it have only the summaries, which place a
// change to within one summary and miss a lesson passed between two.
#pragma once

#include <limits>
#include <optional>
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
  // the measure its last completion passed the threshold at (metrics/lessons.csv); NaN: none
  double completed_at = std::numeric_limits<double>::quiet_NaN();
};

// One row of metrics/lessons.csv.
struct LessonChangeRow {
  std::vector<double> steps;  // [the file's step columns]: total_steps, then <Behavior>_step
  std::string parameter;
  int from = 0, to = 0;
  bool fell_back = false;
  double measure = std::numeric_limits<double>::quiet_NaN();
};
struct LessonChanges {
  std::vector<std::string> step_columns;  // total_steps, <Behavior>_step, ...
  std::vector<LessonChangeRow> rows;      // in the order they happened
};

// metrics/lessons.csv at `path`; none when the file does not exist; throws naming the file and
// line when a row is malformed.
std::optional<LessonChanges> read_lesson_changes(const std::string& path);

struct LessonTable {
  std::string parameter;             // the curriculum parameter (episodes.csv's lesson_<parameter>)
  std::string behavior;              // whose turns count and whose steps; "" for every row, total
  std::vector<std::string> metrics;  // the episode metrics averaged
  std::vector<LessonSummary> lessons;  // in the order the run first entered them
  bool exact = false;  // entries, steps and stretches from metrics/lessons.csv
};

// The lessons of `parameter` in `run` (read_run_curves; `lesson_names` from its configuration,
// indexed by lesson, may be empty). With `behavior`, steps are that behavior's and only the rows in
// which its steps alone advanced count for episodes and metrics (its turns in self-play). `metrics`
// empty: every episode metric of the file. With `changes` (read_lesson_changes), the entries,
// steps in each lesson up to the last summary, stretches and completions are the changes'.
// Throws naming the problem when the run has no episodes.csv, the parameter, behavior or a metric
// is not in it.
LessonTable summarize_lessons(const RunCurves& run, const std::string& parameter,
                              const std::string& behavior, std::vector<std::string> metrics,
                              const std::vector<std::string>& lesson_names,
                              const std::optional<LessonChanges>& changes = std::nullopt);

// The curriculum parameters of `run`'s episodes.csv (its lesson_<name> columns), sorted.
std::vector<std::string> curriculum_parameters(const RunCurves& run);

// The table as Markdown (steps as integers, metrics with `decimals` decimals) and as one JSON object.
std::string lesson_table_markdown(const LessonTable& table, int decimals);
std::string lesson_table_json(const LessonTable& table);

}  // namespace rlt
