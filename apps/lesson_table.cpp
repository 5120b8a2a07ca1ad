#include "apps/lesson_table.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>

#include "rl/core/json.h"

namespace rlt {

namespace {

std::string joined(const std::vector<std::string>& names) {
  std::string out;
  for (const auto& n : names) out += (out.empty() ? "" : ", ") + n;
  return out.empty() ? "none" : out;
}

// the column `name` of the run's episodes.csv; throws naming what the file has instead
int require_column(const CsvTable& table, const std::string& name, const std::string& what,
                   const std::vector<std::string>& instead) {
  const int c = table.column(name);
  if (c < 0) throw std::runtime_error(what + " is not in metrics/episodes.csv (it has: " +
                                      joined(instead) + ")");
  return c;
}

std::string integer_text(double v) {
  if (!std::isfinite(v)) return "-";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.0f", v);
  return buf;
}

}  // namespace

std::vector<std::string> curriculum_parameters(const RunCurves& run) {
  std::vector<std::string> out;
  for (const auto& c : run.episodes.columns)
    if (c.rfind("lesson_", 0) == 0) out.push_back(c.substr(7));
  std::sort(out.begin(), out.end());
  return out;
}

LessonTable summarize_lessons(const RunCurves& run, const std::string& parameter,
                              const std::string& behavior, std::vector<std::string> metrics,
                              const std::vector<std::string>& lesson_names) {
  const CsvTable& table = run.episodes;
  if (table.columns.empty())
    throw std::runtime_error("the run has no metrics/episodes.csv (its env reports no episode "
                             "metrics, or no summary was logged yet)");
  const int lesson_column = require_column(table, "lesson_" + parameter,
                                           "curriculum parameter '" + parameter + "'",
                                           curriculum_parameters(run));
  // each behavior's step column, the counted behavior's first
  std::vector<int> step_columns;
  int counted = -1;
  for (const auto& b : run.behaviors) {
    const int c = table.column(b + "_step");
    if (c < 0) continue;
    if (b == behavior) counted = int(step_columns.size());
    step_columns.push_back(c);
  }
  if (!behavior.empty() && counted < 0)
    throw std::runtime_error("behavior '" + behavior + "' has no steps in metrics/episodes.csv " +
                             "(the run's behaviors: " + joined(run.behaviors) + ")");
  std::vector<std::string> available;
  for (const auto& c : table.columns)
    if (is_episode_metric(c, run)) available.push_back(c);
  if (metrics.empty()) metrics = available;
  std::vector<int> metric_columns;
  for (const auto& m : metrics) {
    if (std::find(available.begin(), available.end(), m) == available.end())
      throw std::runtime_error("episode metric '" + m + "' is not in metrics/episodes.csv (it " +
                               "has: " + joined(available) + ")");
    metric_columns.push_back(table.column(m));
  }
  const int counter = behavior.empty()
                          ? require_column(table, "total_steps", "column 'total_steps'", table.columns)
                          : step_columns[counted];
  const int episodes_column = require_column(table, "episodes", "column 'episodes'", table.columns);

  LessonTable out{parameter, behavior, metrics, {}};
  std::map<int, size_t> index;  // lesson -> its place in out.lessons
  // per lesson and metric: the episode-weighted sum and its episodes
  std::vector<std::vector<std::pair<double, double>>> sums;
  std::vector<double> previous(table.columns.size(), 0.0);  // steps before the first row: 0
  int previous_lesson = std::numeric_limits<int>::min();
  for (const auto& row : table.rows) {
    if (!std::isfinite(row[lesson_column])) continue;  // not a row of this run's curriculum
    const int lesson = int(std::lround(row[lesson_column]));
    auto [it, fresh] = index.emplace(lesson, out.lessons.size());
    if (fresh) {
      LessonSummary s;
      s.lesson = lesson;
      if (lesson >= 0 && lesson < int(lesson_names.size())) s.name = lesson_names[lesson];
      s.entered = previous[counter];
      s.means.assign(metrics.size(), std::numeric_limits<double>::quiet_NaN());
      out.lessons.push_back(s);
      sums.emplace_back(metrics.size(), std::make_pair(0.0, 0.0));
    }
    LessonSummary& s = out.lessons[it->second];
    if (lesson != previous_lesson) ++s.visits;
    previous_lesson = lesson;
    s.steps += row[counter] - previous[counter];
    // with a behavior, the rows of its turns: its steps advanced and no other behavior's did
    bool counts = true;
    if (!behavior.empty())
      for (size_t b = 0; b < step_columns.size(); ++b) {
        const bool advanced = row[step_columns[b]] > previous[step_columns[b]];
        if (advanced != (int(b) == counted)) counts = false;
      }
    const double episodes = row[episodes_column];
    if (counts && std::isfinite(episodes) && episodes > 0) {
      s.episodes += episodes;
      for (size_t m = 0; m < metrics.size(); ++m) {
        const double v = row[metric_columns[m]];
        if (!std::isfinite(v)) continue;  // a row written before the metric existed
        sums[it->second][m].first += v * episodes;
        sums[it->second][m].second += episodes;
      }
    }
    for (size_t c = 0; c < row.size(); ++c)
      if (std::isfinite(row[c])) previous[c] = row[c];
  }
  for (size_t l = 0; l < out.lessons.size(); ++l)
    for (size_t m = 0; m < metrics.size(); ++m)
      if (sums[l][m].second > 0) out.lessons[l].means[m] = sums[l][m].first / sums[l][m].second;
  return out;
}

std::string lesson_table_markdown(const LessonTable& table, int decimals) {
  const std::string counter = table.behavior.empty() ? "total" : table.behavior;
  std::ostringstream out;
  out << "| lesson | name | entered at (" << counter << " steps) | " << counter
      << " steps in it | visits | episodes";
  for (const auto& m : table.metrics) out << " | " << m;
  out << " |\n|---:|---|---:|---:|---:|---:";
  for (size_t m = 0; m < table.metrics.size(); ++m) out << "|---:";
  out << "|\n";
  for (const auto& s : table.lessons) {
    out << "| " << s.lesson << " | " << (s.name.empty() ? "-" : s.name) << " | "
        << integer_text(s.entered) << " | " << integer_text(s.steps) << " | " << s.visits << " | "
        << integer_text(s.episodes);
    for (double v : s.means) {
      char buf[32];
      std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
      out << " | " << (std::isfinite(v) ? buf : "-");
    }
    out << " |\n";
  }
  return out.str();
}

std::string lesson_table_json(const LessonTable& table) {
  std::ostringstream out;
  out << "{\"parameter\":" << json_string(table.parameter)
      << ",\"behavior\":" << (table.behavior.empty() ? "null" : json_string(table.behavior))
      << ",\"lessons\":[";
  for (size_t l = 0; l < table.lessons.size(); ++l) {
    const auto& s = table.lessons[l];
    out << (l ? "," : "") << "{\"lesson\":" << s.lesson << ",\"name\":" << json_string(s.name)
        << ",\"entered\":" << json_number(s.entered) << ",\"steps\":" << json_number(s.steps)
        << ",\"visits\":" << s.visits << ",\"episodes\":" << json_number(s.episodes)
        << ",\"metrics\":{";
    for (size_t m = 0; m < table.metrics.size(); ++m)
      out << (m ? "," : "") << json_string(table.metrics[m]) << ":" << json_number(s.means[m]);
    out << "}}";
  }
  out << "]}\n";
  return out.str();
}

}  // namespace rlt
