// rlt lessons: where a run spent its curriculum, lesson by lesson, with the env's episode metrics.
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include "apps/command_line.h"
#include "apps/commands.h"
#include "apps/learning_curves.h"
#include "apps/lesson_table.h"
#include "rl/config/config_parser.h"
#include "rl/trainer/run_folder.h"

namespace fs = std::filesystem;

namespace rlt {

const char* const kLessonsHelp = R"(Usage: rlt lessons RUN_DIR [options]

Prints, for each lesson of a curriculum a training run has entered, the step at which it entered
it, the steps it spent there, how many separate stretches that took (a fallback adds one), the
measure its last completion passed the threshold at, and the mean of every episode metric of the
env over the episodes played there (each summary's mean weighted by its episodes), as a Markdown
table. The entries, steps, stretches and completions come from metrics/lessons.csv, one row per
lesson change at the steps it happened; the metrics from metrics/episodes.csv, one row per
summary, each counted in the lesson current when it was written (a lesson passed between two
summaries has no metrics). Runs trained before lessons.csv was written have the summaries only:
their changes are placed to within one summary, a lesson passed between two is missing and there
is no completed-at column. Lesson names come from the run's configuration.yaml. Works while the
run is still training.

Options:
  --parameter NAME  the curriculum parameter (default: the run's only one; needed when it has
                    several)
  --behavior NAME   count that behavior's steps, and only the summaries in which its steps alone
                    advanced (its turns in self-play) for the episodes and metrics (default: total
                    steps and every summary)
  --metric NAME     an episode metric to show (repeat; default: all of them)
  --decimals N      decimals of the metrics (default 2)
  --json            one JSON object instead of the table

Example:
  rlt lessons results/hide_and_seek --behavior Hider --metric fort_rate --metric openings_closed
)";

namespace {

// the lesson names of `parameter` in the run's configuration.yaml; none without the file, and
// none with a warning when it cannot be read (the table needs only the metrics)
std::vector<std::string> lesson_names(const std::string& dir, const std::string& parameter) {
  const RunFolder run = run_folder_at(dir);
  if (!fs::exists(run.config_path())) return {};
  RunConfig config;
  try {
    config = load_run_config(run.config_path());
  } catch (const std::exception& e) {
    std::cerr << "rlt lessons: warning: lessons left unnamed: " << e.what() << "\n";
    return {};
  }
  std::vector<std::string> names;
  const auto it = config.environment_parameters.find(parameter);
  if (it != config.environment_parameters.end())
    for (const auto& lesson : it->second.curriculum) names.push_back(lesson.name);
  return names;
}

}  // namespace

int run_lessons(const std::vector<std::string>& args) {
  CommandLine cl(args, {"--json"}, {"--parameter", "--behavior", "--metric", "--decimals"});
  if (cl.positional().size() != 1) throw UsageError("expected one RUN_DIR");
  const std::string dir = cl.positional()[0];
  const int decimals = int(cl.integer("--decimals", 2, 0));
  if (decimals > 12) throw UsageError("--decimals must be at most 12");
  const RunCurves run = read_run_curves(dir, dir);
  if (run.episodes.columns.empty())
    throw std::runtime_error(dir + " has no metrics/episodes.csv: its env reports no episode "
                             "metrics, or no summary was logged yet");
  const auto parameters = curriculum_parameters(run);
  std::string parameter = cl.value("--parameter");
  if (parameter.empty()) {
    if (parameters.empty())
      throw std::runtime_error(dir + " has no curriculum (no lesson_ column in "
                               "metrics/episodes.csv)");
    if (parameters.size() > 1) {
      std::string list;
      for (const auto& p : parameters) list += " " + p;
      throw UsageError("the run has several curricula; name one with --parameter:" + list);
    }
    parameter = parameters[0];
  }
  const LessonTable table =
      summarize_lessons(run, parameter, cl.value("--behavior"), cl.values("--metric"),
                        lesson_names(dir, parameter),
                        read_lesson_changes(run_folder_at(dir).lesson_changes_path()));
  std::cout << (cl.has("--json") ? lesson_table_json(table) : lesson_table_markdown(table, decimals));
  return 0;
}

}  // namespace rlt
