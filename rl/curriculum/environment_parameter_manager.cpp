// Environment parameters over training: sampling, lesson advances and the saved state.
#include "rl/curriculum/environment_parameter_manager.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <utility>

#include "rl/env_api/uniform_random.h"

namespace rlt {

namespace {

constexpr double kTwoPi = 6.283185307179586476925286766559;

// A standard normal draw by the Box-Muller transform: two uniform draws, the cosine branch.
double standard_normal(std::mt19937_64& rng) {
  const double u1 = 1.0 - uniform01(rng);  // in (0, 1]: log stays finite
  const double u2 = uniform01(rng);
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(kTwoPi * u2);
}

// Interval i with probability proportional to its length, then uniform inside it (one draw).
// All intervals of length 0: one of them uniformly (one draw), at its point.
double multi_range_uniform(std::mt19937_64& rng, const std::vector<std::array<float, 2>>& ranges) {
  if (ranges.empty()) return 0.0;
  double total = 0.0;
  for (const auto& range : ranges) total += double(range[1]) - double(range[0]);
  if (!(total > 0.0)) return ranges[uniform_int(rng, int(ranges.size()))][0];
  double offset = uniform01(rng) * total;
  size_t pick = ranges.size();
  for (size_t i = 0; i < ranges.size(); ++i) {
    const double length = double(ranges[i][1]) - double(ranges[i][0]);
    if (length <= 0.0) continue;
    pick = i;  // the last interval with a length takes what rounding leaves over
    if (offset < length) break;
    offset -= length;
  }
  return std::min(double(ranges[pick][1]), double(ranges[pick][0]) + offset);
}

float draw(const SamplerSettings& sampler, std::mt19937_64& rng) {
  switch (sampler.type) {
    case SamplerType::kConstant:
      return sampler.value;
    case SamplerType::kUniform:
      return float(uniform(rng, sampler.min_value, sampler.max_value));
    case SamplerType::kGaussian:
      return float(double(sampler.mean) + double(sampler.st_dev) * standard_normal(rng));
    case SamplerType::kMultiRangeUniform:
      return float(multi_range_uniform(rng, sampler.intervals));
  }
  return sampler.value;
}

// Shortest decimal text that reads back to exactly `value` (finite values only).
std::string number_text(double value) {
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof(buffer), value);
  return std::string(buffer, result.ptr);
}

std::string json_quote(const std::string& text) {
  std::string out = "\"";
  for (const char c : text) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      char escape[8];
      std::snprintf(escape, sizeof(escape), "\\u%04x", c);
      out += escape;
    } else {
      out += c;
    }
  }
  return out + "\"";
}

[[noreturn]] void bad_state(const std::string& problem) {
  throw std::runtime_error("environment parameter state: " + problem);
}

double read_number(const YAML::Node& node, const std::string& what) {
  if (!node.IsScalar()) bad_state(what + ": expected a number");
  const std::string& text = node.Scalar();
  double value = 0.0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc() || end != text.data() + text.size() || !std::isfinite(value)) {
    bad_state(what + ": expected a finite number, got '" + text + "'");
  }
  return value;
}

// The key of a metric criterion's buffer: the metric, then "@behavior" when it names one.
std::string metric_key(const std::string& metric, const std::string& behavior) {
  return behavior.empty() ? metric : metric + "@" + behavior;
}

// The key of a fallback buffer: what the criterion measures, reward or metric.
std::string fallback_key(const CompletionCriteria& criteria) {
  return criteria.measure == CompletionMeasure::kMetric
             ? "metric:" + metric_key(criteria.metric, criteria.behavior)
             : "reward:" + criteria.behavior;
}

// The value a lesson's staircase starts from: the lesson's constant for the staircase's parameter.
double staircase_start(const Lesson& lesson, const std::string& curriculum) {
  const std::string& parameter = lesson.staircase->parameter;
  if (parameter == curriculum) return lesson.value.value;
  const auto found = lesson.other_parameters.find(parameter);
  return found == lesson.other_parameters.end() ? 0.0 : double(found->second.value);
}

// `value` held within the staircase of `lesson` (between its start and its end).
double clamp_to_staircase(const Lesson& lesson, const std::string& curriculum, double value) {
  const double start = staircase_start(lesson, curriculum), end = lesson.staircase->end;
  return std::clamp(value, std::min(start, end), std::max(start, end));
}

}  // namespace

void EnvironmentParameterManager::enter_lesson(const std::string& name, ParameterState& state,
                                               int lesson) const {
  state.lesson = lesson;
  state.furthest = std::max(state.furthest, lesson);
  state.told_waiting = false;
  const Lesson& entered = settings_.at(name).curriculum[lesson];
  state.staircase = entered.staircase ? staircase_start(entered, name) : 0.0;
}

void EnvironmentParameterManager::move_staircases(bool metric, const std::string& key,
                                                  double value) {
  if (staircases_follow_only_) return;
  for (auto& [name, state] : state_) {
    const Lesson& lesson = settings_.at(name).curriculum[state.lesson];
    if (!lesson.staircase || !lesson.completion_criteria) continue;
    const CompletionCriteria& criteria = *lesson.completion_criteria;
    const bool measures_metric = criteria.measure == CompletionMeasure::kMetric;
    if (measures_metric != metric) continue;
    if ((metric ? metric_key(criteria.metric, criteria.behavior) : criteria.behavior) != key)
      continue;
    const Staircase& staircase = *lesson.staircase;
    const double start = staircase_start(lesson, name);
    const double toward_end = staircase.end > start ? 1.0 : -1.0;
    const double step = value > criteria.threshold ? staircase.step_up : -staircase.step_down;
    state.staircase = clamp_to_staircase(lesson, name, state.staircase + toward_end * step);
  }
}

EnvironmentParameterManager::EnvironmentParameterManager(
    std::map<std::string, EnvironmentParameterSettings> settings)
    : settings_(std::move(settings)) {
  for (const auto& [name, parameter] : settings_) {
    if (!parameter.is_curriculum()) continue;
    state_[name] = ParameterState{};
    enter_lesson(name, state_[name], 0);
    for (const Lesson& lesson : parameter.curriculum) {
      if (!lesson.completion_criteria) continue;
      const CompletionCriteria& criteria = *lesson.completion_criteria;
      const bool metric = criteria.measure == CompletionMeasure::kMetric;
      const std::string key =
          metric ? metric_key(criteria.metric, criteria.behavior) : criteria.behavior;
      if (metric) metric_sources_[key] = MetricSource{criteria.metric, criteria.behavior};
      int& capacity = (metric ? metric_capacity_ : capacity_)[key];
      capacity = std::max({capacity, 1, criteria.min_lesson_length});
      (metric ? metrics_ : rewards_)[key];
      if (criteria.fallback_threshold && criteria.measure != CompletionMeasure::kProgress) {
        int& length = fallback_capacity_[fallback_key(criteria)];
        length = std::max(length, criteria.fallback_episodes());
        fallbacks_[fallback_key(criteria)];
      }
    }
  }
}

Parameters EnvironmentParameterManager::sample(std::mt19937_64& rng) const {
  Parameters values;
  for (const auto& [name, parameter] : settings_) {
    const SamplerSettings& sampler = parameter.is_curriculum()
                                         ? parameter.curriculum[state_.at(name).lesson].value
                                         : parameter.sampler;
    values[name] = draw(sampler, rng);
  }
  // the other parameters of each curriculum's current lesson, after every entry's own value
  for (const auto& [name, parameter] : settings_) {
    if (!parameter.is_curriculum()) continue;
    for (const auto& [other, sampler] : parameter.curriculum[state_.at(name).lesson].other_parameters)
      values[other] = draw(sampler, rng);
  }
  // a staircase replaces its parameter's constant (which took no draw)
  for (const auto& [name, state] : state_) {
    const Lesson& lesson = settings_.at(name).curriculum[state.lesson];
    if (lesson.staircase) values[lesson.staircase->parameter] = float(state.staircase);
  }
  return values;
}

int64_t EnvironmentParameterManager::max_steps(const std::string& behavior, int64_t own) const {
  int64_t budget = own;
  for (const auto& [name, state] : state_) {
    const std::vector<Lesson>& lessons = settings_.at(name).curriculum;
    for (int i = 0; i <= state.furthest; ++i) {
      const auto found = lessons[i].behavior_max_steps.find(behavior);
      if (found != lessons[i].behavior_max_steps.end()) budget = std::max(budget, found->second);
    }
  }
  return budget;
}

Parameters EnvironmentParameterManager::sample(uint64_t seed) const {
  std::mt19937_64 rng(seed);
  return sample(rng);
}

std::map<std::string, int> EnvironmentParameterManager::lessons() const {
  std::map<std::string, int> result;
  for (const auto& [name, state] : state_) result[name] = state.lesson;
  return result;
}

std::map<std::string, int> EnvironmentParameterManager::furthest_lessons() const {
  std::map<std::string, int> result;
  for (const auto& [name, state] : state_) result[name] = state.furthest;
  return result;
}

std::map<std::string, std::string> EnvironmentParameterManager::lesson_names() const {
  std::map<std::string, std::string> result;
  for (const auto& [name, state] : state_) {
    result[name] = settings_.at(name).curriculum[state.lesson].name;
  }
  return result;
}

namespace {

// Appends `value` to the buffer `key` of `buffers` when `capacities` has that key and the value is
// finite, dropping the oldest values beyond the capacity.
void record(const std::map<std::string, int>& capacities,
            std::map<std::string, std::deque<double>>& buffers, const std::string& key,
            double value) {
  const auto capacity = capacities.find(key);
  if (capacity == capacities.end() || !std::isfinite(value)) return;
  std::deque<double>& buffer = buffers[key];
  buffer.push_back(value);
  while (int(buffer.size()) > capacity->second) buffer.pop_front();
}

std::vector<double> as_vector(const std::map<std::string, std::deque<double>>& buffers,
                              const std::string& key) {
  const auto found = buffers.find(key);
  if (found == buffers.end()) return {};
  return std::vector<double>(found->second.begin(), found->second.end());
}

}  // namespace

void EnvironmentParameterManager::add_episode_reward(const std::string& behavior, double reward) {
  if (!capacity_.count(behavior) || !std::isfinite(reward)) return;
  record(capacity_, rewards_, behavior, reward);
  move_staircases(false, behavior, reward);
  if (!fallbacks_.empty()) record(fallback_capacity_, fallbacks_, "reward:" + behavior, reward);
}

void EnvironmentParameterManager::add_episode_metrics(
    const std::map<std::string, float>& metrics,
    const std::vector<std::string>& learned_throughout) {
  for (const auto& [key, source] : metric_sources_) {
    const auto value = metrics.find(source.metric);
    if (value == metrics.end()) continue;
    if (!source.behavior.empty() &&
        std::find(learned_throughout.begin(), learned_throughout.end(), source.behavior) ==
            learned_throughout.end())
      continue;
    if (!std::isfinite(value->second)) continue;
    record(metric_capacity_, metrics_, key, value->second);
    move_staircases(true, key, value->second);
    if (!fallbacks_.empty()) record(fallback_capacity_, fallbacks_, "metric:" + key, value->second);
  }
}

std::vector<double> EnvironmentParameterManager::metric_buffer(const std::string& metric,
                                                               const std::string& behavior) const {
  return as_vector(metrics_, metric_key(metric, behavior));
}

void EnvironmentParameterManager::check_metric_names(const std::vector<std::string>& names) const {
  for (const auto& [parameter, settings] : settings_) {
    if (!settings.is_curriculum()) continue;
    for (const Lesson& lesson : settings.curriculum) {
      if (!lesson.completion_criteria ||
          lesson.completion_criteria->measure != CompletionMeasure::kMetric)
        continue;
      const std::string& metric = lesson.completion_criteria->metric;
      if (std::find(names.begin(), names.end(), metric) != names.end()) continue;
      std::string known;
      for (const std::string& name : names) known += (known.empty() ? "" : ", ") + name;
      throw std::invalid_argument("environment_parameters." + parameter + ", lesson '" +
                                  lesson.name +
                                  "': completion_criteria measures the episode metric '" + metric +
                                  "', which the environment does not report (it reports: " +
                                  (known.empty() ? "none" : known) + ")");
    }
  }
}

void EnvironmentParameterManager::check_strategy_names(
    const std::vector<std::string>& names) const {
  for (const auto& [parameter, settings] : settings_) {
    if (!settings.is_curriculum()) continue;
    for (const Lesson& lesson : settings.curriculum) {
      if (!lesson.completion_criteria) continue;
      for (const std::string& strategy : lesson.completion_criteria->after_emerged) {
        if (std::find(names.begin(), names.end(), strategy) != names.end()) continue;
        std::string known;
        for (const std::string& name : names) known += (known.empty() ? "" : ", ") + name;
        throw std::invalid_argument(
            "environment_parameters." + parameter + ", lesson '" + lesson.name +
            "': completion_criteria.after_emerged names the strategy '" + strategy +
            "', which the environment does not declare (it declares: " +
            (known.empty() ? "none" : known) + ")");
      }
    }
  }
}

std::vector<double> EnvironmentParameterManager::reward_buffer(const std::string& behavior) const {
  return as_vector(rewards_, behavior);
}

int EnvironmentParameterManager::reward_buffer_capacity(const std::string& behavior) const {
  const auto found = capacity_.find(behavior);
  return found == capacity_.end() ? 0 : found->second;
}

double EnvironmentParameterManager::smoothed_value(const std::string& parameter) const {
  const auto found = state_.find(parameter);
  return found == state_.end() ? 0.0 : found->second.smoothed;
}

std::string EnvironmentParameterManager::fall_back_if_collapsed(const std::string& name,
                                                                ParameterState& state,
                                                                double& measured) {
  const Lesson& lesson = settings_.at(name).curriculum[state.lesson];
  if (state.lesson == 0 || !lesson.completion_criteria) return "";
  const CompletionCriteria& criteria = *lesson.completion_criteria;
  if (!criteria.fallback_threshold || criteria.measure == CompletionMeasure::kProgress) return "";
  const std::deque<double>& values = fallbacks_.at(fallback_key(criteria));
  const int length = criteria.fallback_episodes();
  if (int(values.size()) < length) return "";
  double mean = 0.0;
  for (auto value = values.end() - length; value != values.end(); ++value) mean += *value;
  mean /= double(length);
  if (mean > *criteria.fallback_threshold) return "";
  measured = mean;
  enter_lesson(name, state, state.lesson - 1);
  const std::string what =
      criteria.measure == CompletionMeasure::kMetric ? criteria.metric : "reward";
  return "Curriculum " + name + ": back from lesson " + std::to_string(state.lesson + 1) + " (" +
         lesson.name + ") to " + std::to_string(state.lesson) + " (" +
         settings_.at(name).curriculum[state.lesson].name + "): mean " + what + " " +
         number_text(mean) + " over the last " + std::to_string(length) +
         " episodes, at or below fallback_threshold " + number_text(*criteria.fallback_threshold);
}

void EnvironmentParameterManager::clear_buffers() {
  for (auto& [behavior, rewards] : rewards_) rewards.clear();
  for (auto& [metric, values] : metrics_) values.clear();
  for (auto& [key, values] : fallbacks_) values.clear();
}

bool EnvironmentParameterManager::completes(const CompletionCriteria& criteria,
                                            const std::optional<Staircase>& staircase,
                                            ParameterState& state,
                                            const BehaviorProgress* progress,
                                            double& measured) {
  measured = std::numeric_limits<double>::quiet_NaN();
  const bool metric = criteria.measure == CompletionMeasure::kMetric;
  const std::deque<double>& values =
      metric ? metrics_.at(metric_key(criteria.metric, criteria.behavior))
             : rewards_.at(criteria.behavior);
  if (int(values.size()) < criteria.min_lesson_length) return false;
  if (staircase) return state.staircase == staircase->end;
  if (criteria.measure == CompletionMeasure::kProgress) {
    const double fraction =
        progress->max_steps > 0 ? double(progress->steps) / double(progress->max_steps) : 0.0;
    measured = fraction;
    return fraction > criteria.threshold;
  }
  if (values.empty()) return false;
  double measure = 0.0;
  for (const double value : values) measure += value;
  measure /= double(values.size());
  if (criteria.signal_smoothing) {
    measure = 0.25 * state.smoothed + 0.75 * measure;
    state.smoothed = measure;
  }
  measured = measure;
  return measure > criteria.threshold;
}

LessonUpdate EnvironmentParameterManager::update(
    const std::map<std::string, BehaviorProgress>& progress, const std::set<std::string>& emerged) {
  LessonUpdate result;
  for (auto& [name, state] : state_) {
    const std::vector<Lesson>& lessons = settings_.at(name).curriculum;
    const Lesson& lesson = lessons[state.lesson];
    if (!lesson.completion_criteria) continue;
    const CompletionCriteria& criteria = *lesson.completion_criteria;
    const auto behavior = progress.find(criteria.behavior);
    const bool measured_on_steps = criteria.measure != CompletionMeasure::kMetric;
    if (measured_on_steps && behavior == progress.end()) continue;  // no trainer yet
    const bool last = state.lesson + 1 >= int(lessons.size());      // the last lesson never ends
    double measured = 0.0;
    if (!last && completes(criteria, lesson.staircase, state,
                           measured_on_steps ? &behavior->second : nullptr, measured)) {
      const auto missing =
          std::find_if(criteria.after_emerged.begin(), criteria.after_emerged.end(),
                       [&](const std::string& strategy) { return !emerged.count(strategy); });
      if (missing == criteria.after_emerged.end()) {
        result.changes.push_back({name, state.lesson, state.lesson + 1, false, measured});
        enter_lesson(name, state, state.lesson + 1);
        result.changed = true;
        if (criteria.require_reset) result.require_reset = true;
        continue;
      }
      if (!state.told_waiting) {
        state.told_waiting = true;
        result.waits.push_back("Curriculum " + name + ": lesson " +
                               std::to_string(state.lesson) + " (" + lesson.name +
                               ") met its threshold and goes on until the strategy " + *missing +
                               " has emerged (after_emerged)");
      }
    }
    const int before = state.lesson;
    const std::string sentence = fall_back_if_collapsed(name, state, measured);
    if (sentence.empty()) continue;
    result.changes.push_back({name, before, state.lesson, true, measured});
    result.changed = true;
    result.fallbacks.push_back(sentence);
  }
  if (result.changed) clear_buffers();
  return result;
}

LessonUpdate EnvironmentParameterManager::follow(
    const std::map<std::string, int>& lessons,
    const std::map<std::string, double>& staircase_values) {
  LessonUpdate result;
  for (auto& [name, state] : state_) {
    const auto it = lessons.find(name);
    if (it == lessons.end() || it->second == state.lesson) continue;
    const auto& curriculum = settings_.at(name).curriculum;
    if (it->second < 0 || it->second >= int(curriculum.size()))
      throw std::invalid_argument("lesson " + std::to_string(it->second) + " of " + name +
                                  " does not exist");
    // the criteria of the lessons left decide require_reset, as in update()
    for (int l = state.lesson; l < it->second; ++l) {
      const auto& criteria = curriculum[l].completion_criteria;
      if (criteria && criteria->require_reset) result.require_reset = true;
    }
    enter_lesson(name, state, it->second);
    result.changed = true;
  }
  if (result.changed) clear_buffers();
  for (auto& [name, state] : state_) {
    const auto value = staircase_values.find(name);
    const Lesson& lesson = settings_.at(name).curriculum[state.lesson];
    if (value == staircase_values.end() || !lesson.staircase || !std::isfinite(value->second))
      continue;
    state.staircase = clamp_to_staircase(lesson, name, value->second);
  }
  return result;
}

std::map<std::string, double> EnvironmentParameterManager::staircase_values() const {
  std::map<std::string, double> values;
  for (const auto& [name, state] : state_)
    if (settings_.at(name).curriculum[state.lesson].staircase) values[name] = state.staircase;
  return values;
}

std::string EnvironmentParameterManager::serialize() const {
  std::string text = "{\"parameters\": {";
  bool first = true;
  for (const auto& [name, state] : state_) {
    text += (first ? "" : ", ") + json_quote(name) +
            ": {\"lesson\": " + std::to_string(state.lesson) +
            ", \"lesson_name\": " + json_quote(settings_.at(name).curriculum[state.lesson].name) +
            ", \"smoothed_value\": " + number_text(state.smoothed) +
            ", \"furthest_lesson\": " + std::to_string(state.furthest) +
            (settings_.at(name).curriculum[state.lesson].staircase
                 ? ", \"staircase_value\": " + number_text(state.staircase)
                 : std::string()) +
            "}";
    first = false;
  }
  const auto buffers_text = [](const std::map<std::string, std::deque<double>>& buffers) {
    std::string text;
    for (const auto& [key, values] : buffers) {
      text += (text.empty() ? "" : ", ") + json_quote(key) + ": [";
      for (size_t i = 0; i < values.size(); ++i) {
        text += (i == 0 ? "" : ", ") + number_text(values[i]);
      }
      text += "]";
    }
    return text;
  };
  text += "}, \"reward_buffers\": {" + buffers_text(rewards_) + "}";
  if (!metrics_.empty()) text += ", \"metric_buffers\": {" + buffers_text(metrics_) + "}";
  if (!fallbacks_.empty()) text += ", \"fallback_buffers\": {" + buffers_text(fallbacks_) + "}";
  return text + "}";
}

void EnvironmentParameterManager::deserialize(const std::string& state) {
  YAML::Node root;
  try {
    root = YAML::Load(state);
  } catch (const YAML::Exception& error) {
    bad_state(std::string("cannot read it: ") + error.what());
  }
  if (!root.IsMap()) bad_state("expected a mapping with parameters and reward_buffers");

  std::map<std::string, ParameterState> states;
  for (const auto& [name, unused] : state_) states[name] = ParameterState{};
  const YAML::Node parameters = root["parameters"];
  if (parameters && !parameters.IsNull()) {
    if (!parameters.IsMap()) bad_state("parameters: expected a mapping");
    for (const auto& entry : parameters) {
      const std::string name = entry.first.Scalar();
      const auto found = states.find(name);
      if (found == states.end()) continue;  // no longer a curriculum parameter
      const YAML::Node values = entry.second;
      if (!values.IsMap()) bad_state("parameters." + name + ": expected a mapping");
      const int lesson_count = int(settings_.at(name).curriculum.size());
      const double lesson = read_number(values["lesson"], "parameters." + name + ".lesson");
      if (lesson != std::floor(lesson) || lesson < 0 || lesson >= lesson_count) {
        bad_state("parameters." + name + ".lesson: lesson " + number_text(lesson) +
                  " does not exist (the curriculum has " + std::to_string(lesson_count) +
                  " lessons)");
      }
      // a config whose lessons changed since the state was saved would resume elsewhere
      const std::string& expected = settings_.at(name).curriculum[int(lesson)].name;
      if (values["lesson_name"] && values["lesson_name"].IsScalar() &&
          values["lesson_name"].Scalar() != expected) {
        bad_state("parameters." + name + ".lesson_name: the run was in lesson " +
                  number_text(lesson) + " '" + values["lesson_name"].Scalar() +
                  "', which the config calls '" + expected +
                  "': its curriculum changed since (start a new run, or restore the old lessons)");
      }
      enter_lesson(name, found->second, int(lesson));  // its staircase at its start
      found->second.furthest = int(lesson);  // states from before fallbacks: never went back
      const Lesson& at = settings_.at(name).curriculum[int(lesson)];
      if (at.staircase && values["staircase_value"]) {
        const double value =
            read_number(values["staircase_value"], "parameters." + name + ".staircase_value");
        if (clamp_to_staircase(at, name, value) != value) {
          bad_state("parameters." + name + ".staircase_value: " + number_text(value) +
                    " is outside lesson '" + expected + "''s staircase (from " +
                    number_text(staircase_start(at, name)) + " to " +
                    number_text(at.staircase->end) + ")");
        }
        found->second.staircase = value;
      }
      if (values["furthest_lesson"]) {
        const double furthest =
            read_number(values["furthest_lesson"], "parameters." + name + ".furthest_lesson");
        if (furthest != std::floor(furthest) || furthest < lesson || furthest >= lesson_count) {
          bad_state("parameters." + name + ".furthest_lesson: " + number_text(furthest) +
                    " is not a lesson at or after lesson " + number_text(lesson));
        }
        found->second.furthest = int(furthest);
      }
      if (values["smoothed_value"]) {
        found->second.smoothed =
            read_number(values["smoothed_value"], "parameters." + name + ".smoothed_value");
      }
    }
  }

  // the buffers `field` of the state, for the keys `capacities` has (the others are no longer
  // measured), each cut to its capacity
  const auto read_buffers = [&root](const char* field,
                                    const std::map<std::string, int>& capacities) {
    std::map<std::string, std::deque<double>> buffers;
    for (const auto& [key, unused] : capacities) buffers[key];
    const YAML::Node node = root[field];
    if (!node || node.IsNull()) return buffers;
    if (!node.IsMap()) bad_state(std::string(field) + ": expected a mapping");
    for (const auto& entry : node) {
      const std::string key = entry.first.Scalar();
      const auto found = buffers.find(key);
      if (found == buffers.end()) continue;
      const std::string where = std::string(field) + "." + key;
      if (!entry.second.IsSequence()) bad_state(where + ": expected a list");
      for (const auto& value : entry.second) found->second.push_back(read_number(value, where));
      while (int(found->second.size()) > capacities.at(key)) found->second.pop_front();
    }
    return buffers;
  };
  auto rewards = read_buffers("reward_buffers", capacity_);
  auto metrics = read_buffers("metric_buffers", metric_capacity_);
  auto fallbacks = read_buffers("fallback_buffers", fallback_capacity_);
  state_ = std::move(states);
  rewards_ = std::move(rewards);
  metrics_ = std::move(metrics);
  fallbacks_ = std::move(fallbacks);
}

}  // namespace rlt
