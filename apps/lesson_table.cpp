#include "apps/lesson_table.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>

#include "rl/core/csv_line.h"
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

// `field` of `path`'s line `number` as a number; throws naming them when it is not one
double number_field(const std::string& field, const std::string& path, int number,
                    const std::string& column) {
  char* end = nullptr;
  const double v = std::strtod(field.c_str(), &end);
  if (field.empty() || *end != '\0')
    throw std::runtime_error(path + ":" + std::to_string(number) + ": " + column + " '" + field +
                             "' is not a number");
  return v;
}

// the stretches of `parameter`'s lessons in `changes`, counted on the step column `counter`, the
// last one running to `end`: each lesson's entry, steps, stretches and last completion, in the
// order first entered (`first`: the lesson the run began in when no change says)
struct Stretches {
  std::vector<int> order;
  std::map<int, LessonSummary> of;
};
Stretches lesson_stretches(const LessonChanges& changes, const std::string& parameter,
                           size_t counter, int first, double end) {
  std::vector<const LessonChangeRow*> mine;
  for (const auto& row : changes.rows)
    if (row.parameter == parameter) mine.push_back(&row);
  Stretches out;
  int current = mine.empty() ? first : mine.front()->from;
  double since = 0.0;
  const auto enter = [&](int lesson, double step) {
    auto [it, fresh] = out.of.emplace(lesson, LessonSummary{});
    if (fresh) {
      out.order.push_back(lesson);
      it->second.entered = step;
    }
    ++it->second.visits;
    current = lesson;
    since = step;
  };
  enter(current, 0.0);
  for (const LessonChangeRow* row : mine) {
    const double at = row->steps[counter];
    out.of[current].steps += at - since;
    if (!row->fell_back) out.of[current].completed_at = row->measure;
    enter(row->to, at);
  }
  out.of[current].steps += std::max(end, since) - since;
  return out;
}

}  // namespace

std::optional<LessonChanges> read_lesson_changes(const std::string& path) {
  if (!std::filesystem::exists(path)) return std::nullopt;
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read " + path);
  std::string contents((std::istreambuf_iterator<char>(in)), {});
  // a last line without its newline is a write that was cut off
  if (!contents.empty() && contents.back() != '\n') contents.erase(contents.rfind('\n') + 1);
  std::istringstream lines(contents);
  LessonChanges out;
  std::string line;
  if (!std::getline(lines, line)) return out;
  const std::vector<std::string> header = split_csv_line(line);
  const std::vector<std::string> tail = {"parameter", "from_lesson", "to_lesson", "change",
                                         "measure"};
  if (header.size() <= tail.size() || header.front() != "total_steps" ||
      !std::equal(tail.begin(), tail.end(), header.end() - long(tail.size())))
    throw std::runtime_error(path + ":1: expected the header total_steps,...,parameter," +
                             "from_lesson,to_lesson,change,measure, got '" + line + "'");
  std::vector<size_t> step_at;  // the step columns' places
  for (size_t c = 0; c + tail.size() < header.size(); ++c)
    if (header[c] != "elapsed_s") {
      out.step_columns.push_back(header[c]);
      step_at.push_back(c);
    }
  const size_t p = header.size() - tail.size();
  for (int number = 2; std::getline(lines, line); ++number) {
    const std::vector<std::string> f = split_csv_line(line);
    if (f.size() != header.size())
      throw std::runtime_error(path + ":" + std::to_string(number) + ": " +
                               std::to_string(f.size()) + " fields under a header of " +
                               std::to_string(header.size()));
    LessonChangeRow row;
    for (size_t c : step_at) row.steps.push_back(number_field(f[c], path, number, header[c]));
    row.parameter = f[p];
    row.from = int(number_field(f[p + 1], path, number, "from_lesson"));
    row.to = int(number_field(f[p + 2], path, number, "to_lesson"));
    if (f[p + 3] != "completed" && f[p + 3] != "fell_back")
      throw std::runtime_error(path + ":" + std::to_string(number) + ": change '" + f[p + 3] +
                               "' is neither completed nor fell_back");
    row.fell_back = f[p + 3] == "fell_back";
    if (!f[p + 4].empty()) row.measure = number_field(f[p + 4], path, number, "measure");
    out.rows.push_back(row);
  }
  return out;
}

std::vector<std::string> curriculum_parameters(const RunCurves& run) {
  std::vector<std::string> out;
  for (const auto& c : run.episodes.columns)
    if (c.rfind("lesson_", 0) == 0) out.push_back(c.substr(7));
  std::sort(out.begin(), out.end());
  return out;
}

LessonTable summarize_lessons(const RunCurves& run, const std::string& parameter,
                              const std::string& behavior, std::vector<std::string> metrics,
                              const std::vector<std::string>& lesson_names,
                              const std::optional<LessonChanges>& changes) {
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
  if (!changes) return out;

  // the entries, steps and stretches of the changes, the episodes and metrics of the rows
  const std::string counter_name = behavior.empty() ? "total_steps" : behavior + "_step";
  const auto& columns = changes->step_columns;
  const auto at = std::find(columns.begin(), columns.end(), counter_name);
  if (at == columns.end())
    throw std::runtime_error("column '" + counter_name + "' is not in metrics/lessons.csv (it has: " +
                             joined(columns) + ")");
  const int first = out.lessons.empty() ? 0 : out.lessons.front().lesson;
  const Stretches stretches = lesson_stretches(*changes, parameter, size_t(at - columns.begin()),
                                               first, previous[counter]);
  std::vector<LessonSummary> ordered;
  for (const int lesson : stretches.order) {
    const LessonSummary& exact = stretches.of.at(lesson);
    LessonSummary s;
    const auto row = index.find(lesson);
    if (row != index.end()) {
      s = out.lessons[row->second];
    } else {  // passed between two summaries: no row
      s.lesson = lesson;
      if (lesson >= 0 && lesson < int(lesson_names.size())) s.name = lesson_names[lesson];
      s.means.assign(metrics.size(), std::numeric_limits<double>::quiet_NaN());
    }
    s.entered = exact.entered;
    s.steps = exact.steps;
    s.visits = exact.visits;
    s.completed_at = exact.completed_at;
    ordered.push_back(s);
  }
  for (const LessonSummary& s : out.lessons)  // rows of a lesson no change entered (not expected)
    if (!stretches.of.count(s.lesson)) ordered.push_back(s);
  out.lessons = ordered;
  out.exact = true;
  return out;
}

std::string lesson_table_markdown(const LessonTable& table, int decimals) {
  const std::string counter = table.behavior.empty() ? "total" : table.behavior;
  std::ostringstream out;
  const auto decimal_text = [&](double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
    return std::isfinite(v) ? std::string(buf) : std::string("-");
  };
  out << "| lesson | name | entered at (" << counter << " steps) | " << counter
      << " steps in it | visits | episodes";
  if (table.exact) out << " | completed at";
  for (const auto& m : table.metrics) out << " | " << m;
  out << " |\n|---:|---|---:|---:|---:|---:";
  for (size_t m = 0; m < table.metrics.size() + (table.exact ? 1 : 0); ++m) out << "|---:";
  out << "|\n";
  for (const auto& s : table.lessons) {
    out << "| " << s.lesson << " | " << (s.name.empty() ? "-" : s.name) << " | "
        << integer_text(s.entered) << " | " << integer_text(s.steps) << " | " << s.visits << " | "
        << integer_text(s.episodes);
    if (table.exact) out << " | " << decimal_text(s.completed_at);
    for (double v : s.means) out << " | " << decimal_text(v);
    out << " |\n";
  }
  return out.str();
}

std::string lesson_table_json(const LessonTable& table) {
  std::ostringstream out;
  out << "{\"parameter\":" << json_string(table.parameter)
      << ",\"behavior\":" << (table.behavior.empty() ? "null" : json_string(table.behavior))
      << ",\"exact\":" << (table.exact ? "true" : "false")
      << ",\"lessons\":[";
  for (size_t l = 0; l < table.lessons.size(); ++l) {
    const auto& s = table.lessons[l];
    out << (l ? "," : "") << "{\"lesson\":" << s.lesson << ",\"name\":" << json_string(s.name)
        << ",\"entered\":" << json_number(s.entered) << ",\"steps\":" << json_number(s.steps)
        << ",\"visits\":" << s.visits << ",\"episodes\":" << json_number(s.episodes)
        << ",\"completed_at\":" << json_number(s.completed_at)
        << ",\"metrics\":{";
    for (size_t m = 0; m < table.metrics.size(); ++m)
      out << (m ? "," : "") << json_string(table.metrics[m]) << ":" << json_number(s.means[m]);
    out << "}}";
  }
  out << "]}\n";
  return out.str();
}

}  // namespace rlt
