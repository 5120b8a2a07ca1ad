// The values of the environment parameters during training: samplers drawn at each environment
// reset, and curricula whose lessons advance when their completion criteria are met.
//
// Follows ML-Agents' EnvironmentParameterManager
// (mlagents/trainers/environment_parameter_manager.py) together with the reward buffers its
// trainers keep for it:
// - Every parameter starts at its first lesson. A plain sampler is a parameter without lessons.
// - The manager keeps, per behavior named by some completion_criteria, the total environment
//   reward of that behavior's most recent episodes: at most max(1, largest min_lesson_length of
//   the criteria naming the behavior) of them, the oldest dropped first.
// - Our extension, `measure: metric`: the same kind of buffer per env episode metric that some
//   criteria measure (e.g. HideAndSeek's fort_rate), fed with the env's finished episodes. The
//   caller decides which episodes count (training feeds only those played entirely in the
//   current lessons). A metric criterion that names a `behavior` has a buffer of its own, fed
//   only with the episodes that behavior learned from throughout (in self-play, the ones played
//   entirely in its turns): the reward buffers hold only the learning team's episodes too, since
//   the trainers see no others. The mean, smoothing and threshold work as for rewards;
//   min_lesson_length counts those episodes.
// - Our extension, a lesson's `other_parameters`: sample() also draws the other parameters of
//   each curriculum's current lesson, so one curriculum moves several parameters together.
// - update() looks at every curriculum parameter that is not at its last lesson: a lesson whose
//   behavior has recorded fewer than min_lesson_length episodes goes on. Otherwise measure
//   `progress` ends it when steps / max_steps > threshold; measure `reward` computes the mean of
//   the buffer (no episode yet: goes on), replaces it by 0.25 * previous smoothed value + 0.75 *
//   mean when signal_smoothing is on (and keeps that as the new smoothed value), and ends the
//   lesson when the result > threshold. A parameter moves at most one lesson per update(). When
//   any parameter moved, every buffer is cleared. Smoothed values persist across lessons
//   (they start at 0), as in ML-Agents.
// - Our extension, a criterion's `fallback_threshold`: update() also looks at every curriculum
//   parameter past its first lesson whose lesson's criteria set one. When the buffer of the last
//   fallback_length episodes it measures (kept apart from the completion buffers, so that
//   completion is judged as without it) is full and its mean is at or below fallback_threshold,
//   the parameter goes back one lesson; the smoothed value stays. A lesson that completes does not
//   fall back in the same update().
// - Our extension, a criterion's `after_emerged`: a lesson whose measure is met ends only once
//   every strategy it names has emerged (update()'s `emerged`, from the run's StrategyTracker);
//   until then it goes on, and update() says once per lesson entered that it waits. The measure is
//   judged (and smoothed) as without it, so once the strategies have emerged the lesson ends
//   exactly where it would have.
// - Our extension, a lesson's `behavior_max_steps`: max_steps() gives a behavior's step budget
//   as the largest of its own and the budgets of every lesson reached so far (the furthest
//   lesson reached counts, so a budget holds from its lesson on even after a fallback).
// - Our extension, a lesson's `staircase` (rl/config/run_config.h, Staircase): while a curriculum
//   is at such a lesson, sample() gives the staircase's current value for its parameter, and
//   every episode recorded into the buffer its criteria measure moves that value (toward `end`
//   when the episode's measure exceeds the threshold, back toward the start otherwise, never past
//   either; the criteria's threshold judges each episode, and signal_smoothing is not used). The
//   lesson completes when update() finds the value at `end` and min_lesson_length episodes
//   counted; its fallback works as for any lesson. A staircase on the last lesson moves and never
//   completes. Entering a lesson (forward, back or by
//   follow()) starts its staircase at the lesson's own value.
// - serialize() / deserialize() carry the lessons, the smoothed values, the staircases' values and
//   the buffers over --resume exactly.
//
// No LibTorch here. Not thread-safe: one thread drives a manager.
#pragma once

#include <cstdint>
#include <deque>
#include <limits>
#include <map>
#include <optional>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "rl/config/run_config.h"
#include "rl/env_api/spec.h"

namespace rlt {

// What the manager needs to know of one behavior's trainer at an update.
struct BehaviorProgress {
  int64_t steps = 0;      // the behavior's steps so far
  int64_t max_steps = 1;  // its max_steps; progress = steps / max_steps
};

// One parameter's move from one lesson to another in update().
struct LessonChange {
  std::string parameter;
  int from = 0;             // the lesson left
  int to = 0;               // the lesson entered
  bool fell_back = false;   // back by the fallback criterion; else the lesson was completed
  // what decided it: the (smoothed) mean the threshold was passed at, the progress fraction, the
  // fallback window's mean; NaN for a staircase that reached its end
  double measure = std::numeric_limits<double>::quiet_NaN();
};

// The outcome of one update().
struct LessonUpdate {
  bool changed = false;        // at least one parameter moved to its next or previous lesson
  std::vector<LessonChange> changes;  // each move, in the parameters' name order
  bool require_reset = false;  // ... and the completed lesson asked to reset the environments now
  // one sentence per parameter that fell back, naming it, the lessons and the measure
  std::vector<std::string> fallbacks;
  // one sentence per lesson whose measure was met while a strategy it waits for (after_emerged)
  // had not emerged: said once per lesson entered
  std::vector<std::string> waits;
};

class EnvironmentParameterManager {
 public:
  EnvironmentParameterManager() = default;
  explicit EnvironmentParameterManager(
      std::map<std::string, EnvironmentParameterSettings> settings);

  const std::map<std::string, EnvironmentParameterSettings>& settings() const { return settings_; }
  bool empty() const { return settings_.empty(); }

  // The value of every parameter for one environment reset: constants as they are, samplers drawn
  // from `rng` (in the order of the parameter names; a constant takes no draw, a uniform or
  // multirangeuniform sampler one, a gaussian two). The same engine state gives the same values
  // with every standard library.
  Parameters sample(std::mt19937_64& rng) const;
  // Same with an engine seeded with `seed`.
  Parameters sample(uint64_t seed) const;

  // The current lesson of each curriculum parameter (0 = first), and its name.
  std::map<std::string, int> lessons() const;
  std::map<std::string, std::string> lesson_names() const;

  // The step budget of `behavior`: `own` (its max_steps), raised by the behavior_max_steps of
  // the lessons each curriculum has reached.
  int64_t max_steps(const std::string& behavior, int64_t own) const;

  // Records the total environment reward of one finished episode of `behavior` (ML-Agents'
  // trainer.reward_buffer). Ignored when no completion_criteria names the behavior, and when the
  // reward is not finite.
  void add_episode_reward(const std::string& behavior, double reward);
  // The rewards recorded for `behavior` since the last lesson change, oldest first, and how many
  // are kept at most (0 when no completion_criteria names the behavior).
  std::vector<double> reward_buffer(const std::string& behavior) const;
  int reward_buffer_capacity(const std::string& behavior) const;
  // Records the episode metrics of one finished env episode: the ones some criterion measures, when
  // finite. `learned_throughout`: the behaviors whose policies learned from the whole episode;
  // criteria that name a behavior not in it leave the episode out.
  void add_episode_metrics(const std::map<std::string, float>& metrics,
                           const std::vector<std::string>& learned_throughout = {});
  // The values recorded since the last lesson change for the criteria that measure `metric` and
  // name `behavior` (empty: name none), oldest first.
  std::vector<double> metric_buffer(const std::string& metric,
                                    const std::string& behavior = "") const;
  // The furthest lesson each curriculum parameter has reached (lessons() after a fallback is
  // below it).
  std::map<std::string, int> furthest_lessons() const;
  // Throws std::invalid_argument naming the parameter and lesson when a criterion measures an
  // episode metric that is not in `names` (the env's; see VectorEnv::episode_metric_names).
  void check_metric_names(const std::vector<std::string>& names) const;
  // Throws std::invalid_argument naming the parameter and lesson when a criterion's after_emerged
  // names a strategy that is not in `names` (the env's EnvSpec::strategies).
  void check_strategy_names(const std::vector<std::string>& names) const;
  // The smoothed reward or metric measure of a curriculum parameter (0 before its first one).
  double smoothed_value(const std::string& parameter) const;

  // Advances the lessons whose completion criteria are met (see the top of the file). A behavior
  // missing from `progress` has no trainer yet: the lessons that measure it go on. `emerged`: the
  // strategies that have emerged so far (for after_emerged).
  LessonUpdate update(const std::map<std::string, BehaviorProgress>& progress,
                      const std::set<std::string>& emerged = {});
  // Moves to the lessons another manager decided (data-parallel training: rank 0 decides, the
  // others follow): what update() returns when it moved them, buffers cleared alike. Lessons that
  // `lessons` does not name stay. `staircase_values` then sets the staircases of the parameters
  // it names that are at a staircase lesson (a value outside the staircase's range is clamped);
  // moving a staircase is no lesson change.
  LessonUpdate follow(const std::map<std::string, int>& lessons,
                      const std::map<std::string, double>& staircase_values = {});
  // With `true`, recorded episodes no longer move the staircases; only follow() sets them
  // (data-parallel training: the ranks other than 0, so that every rank plays rank 0's values).
  void set_staircases_follow_only(bool follow_only) { staircases_follow_only_ = follow_only; }
  // The current value of each curriculum parameter's staircase (named by the curriculum, not by
  // the parameter the staircase moves), for the curricula at a staircase lesson only.
  std::map<std::string, double> staircase_values() const;

  // The state (lessons, smoothed values, reward buffers) as one JSON object, with every number
  // written so that it reads back bit for bit. Also valid YAML.
  std::string serialize() const;
  // Restores a state that serialize() wrote (given as JSON, or as YAML of the same shape) for the
  // same settings. Parameters the state does not have start at their first lesson; entries of
  // parameters or behaviors the settings do not have are ignored. Throws std::runtime_error when
  // the text is malformed or a lesson does not exist in the settings; the manager is then
  // unchanged.
  void deserialize(const std::string& state);

 private:
  struct ParameterState {
    int lesson = 0;
    int furthest = 0;  // the furthest lesson reached
    double smoothed = 0.0;
    double staircase = 0.0;  // the staircase's value, when the lesson has one
    bool told_waiting = false;  // update() said the lesson waits for a strategy (after_emerged)
  };
  // Moves `state` to `lesson` (furthest included) and starts that lesson's staircase.
  void enter_lesson(const std::string& name, ParameterState& state, int lesson) const;
  // One counted episode whose measure `value` went into the buffer `key` (reward: the behavior;
  // metric: metric_key()) moves the staircases whose lesson's criteria measure that buffer.
  void move_staircases(bool metric, const std::string& key, double value);
  // Whether the lesson measured by `criteria` is complete (updating the smoothed value); a
  // staircase lesson is when its value is at the end. `progress` is the measured behavior's,
  // null for a metric. `measured` gets the value compared with the threshold (NaN: none).
  bool completes(const CompletionCriteria& criteria, const std::optional<Staircase>& staircase,
                 ParameterState& state, const BehaviorProgress* progress, double& measured);
  // Goes back one lesson when the current lesson's fallback criterion says so; returns the
  // sentence for LessonUpdate::fallbacks, or "" when the lesson stays; `measured` gets the
  // fallback window's mean.
  std::string fall_back_if_collapsed(const std::string& name, ParameterState& state,
                                     double& measured);
  void clear_buffers();

  std::map<std::string, EnvironmentParameterSettings> settings_;
  std::map<std::string, ParameterState> state_;        // curriculum parameters only
  bool staircases_follow_only_ = false;                // see set_staircases_follow_only()
  std::map<std::string, int> capacity_;                // reward buffer size per measured behavior
  std::map<std::string, std::deque<double>> rewards_;  // per measured behavior, oldest first
  // Metric buffers are keyed by metric_key(): the metric, and the behavior when the criterion names
  // one.
  struct MetricSource {
    std::string metric;
    std::string behavior;  // empty: every episode counts
  };
  std::map<std::string, MetricSource> metric_sources_;  // per buffer key
  std::map<std::string, int> metric_capacity_;         // buffer size per key
  std::map<std::string, std::deque<double>> metrics_;  // per key, oldest first
  // Fallback buffers, keyed by fallback_key(): the last fallback_length values of what a criterion
  // with a fallback_threshold measures (the largest such length per key).
  std::map<std::string, int> fallback_capacity_;
  std::map<std::string, std::deque<double>> fallbacks_;
};

}  // namespace rlt
