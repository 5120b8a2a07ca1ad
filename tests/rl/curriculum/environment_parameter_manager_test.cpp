// Tests of the environment parameter manager: ML-Agents' lesson rules (min_lesson_length,
// thresholds, one advance per update, progress measure, smoothing, require_reset, reward buffers),
// the samplers' ranges and moments, and the saved state over a resume.
#include "rl/curriculum/environment_parameter_manager.h"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <optional>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

namespace rlt {
namespace {

CompletionCriteria reward_criteria(const std::string& behavior, double threshold,
                                   int min_lesson_length, bool smoothing = false) {
  CompletionCriteria criteria;
  criteria.behavior = behavior;
  criteria.measure = CompletionMeasure::kReward;
  criteria.threshold = threshold;
  criteria.min_lesson_length = min_lesson_length;
  criteria.signal_smoothing = smoothing;
  return criteria;
}

Lesson lesson(const std::string& name, float value,
              std::optional<CompletionCriteria> criteria = std::nullopt) {
  Lesson l;
  l.name = name;
  l.value = SamplerSettings::constant(value);
  l.completion_criteria = std::move(criteria);
  return l;
}

EnvironmentParameterSettings curriculum(std::vector<Lesson> lessons) {
  EnvironmentParameterSettings settings;
  settings.curriculum = std::move(lessons);
  return settings;
}

// Three lessons of `height` measured on the reward of behavior "Jumper".
EnvironmentParameterManager three_lessons(int min_lesson_length, double threshold,
                                          bool smoothing = false) {
  return EnvironmentParameterManager(
      {{"height",
        curriculum(
            {lesson("Low", 0.f, reward_criteria("Jumper", threshold, min_lesson_length, smoothing)),
             lesson("Mid", 4.f, reward_criteria("Jumper", threshold, min_lesson_length, smoothing)),
             lesson("High", 8.f)})}});
}

EnvironmentParameterSettings sampled(SamplerSettings sampler) {
  EnvironmentParameterSettings settings;
  settings.sampler = std::move(sampler);
  return settings;
}

const std::map<std::string, BehaviorProgress> kJumperProgress = {{"Jumper", {100, 1000}}};

TEST(EnvironmentParameterManagerTest, StartsAtTheFirstLesson) {
  EnvironmentParameterManager manager = three_lessons(2, 0.5);
  EXPECT_EQ(manager.lessons(), (std::map<std::string, int>{{"height", 0}}));
  EXPECT_EQ(manager.lesson_names(), (std::map<std::string, std::string>{{"height", "Low"}}));
  EXPECT_EQ(manager.sample(1).at("height"), 0.f);
  EXPECT_EQ(manager.reward_buffer_capacity("Jumper"), 2);
  EXPECT_EQ(manager.reward_buffer_capacity("Other"), 0);
}

TEST(EnvironmentParameterManagerTest, NoAdvanceBelowMinLessonLength) {
  EnvironmentParameterManager manager = three_lessons(3, 0.5);
  manager.add_episode_reward("Jumper", 10.0);
  manager.add_episode_reward("Jumper", 10.0);
  const LessonUpdate update = manager.update(kJumperProgress);
  EXPECT_FALSE(update.changed);
  EXPECT_EQ(manager.lessons().at("height"), 0);
}

TEST(EnvironmentParameterManagerTest, NoAdvanceAtOrBelowTheThreshold) {
  EnvironmentParameterManager manager = three_lessons(2, 0.5);
  manager.add_episode_reward("Jumper", 0.5);
  manager.add_episode_reward("Jumper", 0.5);
  EXPECT_FALSE(manager.update(kJumperProgress).changed);  // the mean must exceed the threshold
  EXPECT_EQ(manager.lessons().at("height"), 0);
  EXPECT_EQ(manager.reward_buffer("Jumper").size(), 2u);  // kept while the lesson goes on
}

TEST(EnvironmentParameterManagerTest, ExactlyOneAdvanceWhenBothAreMet) {
  EnvironmentParameterManager manager = three_lessons(2, 0.5);
  manager.add_episode_reward("Jumper", 1.0);
  manager.add_episode_reward("Jumper", 1.0);
  const LessonUpdate update = manager.update(kJumperProgress);
  EXPECT_TRUE(update.changed);
  EXPECT_FALSE(update.require_reset);
  // One lesson, although lesson "Mid" is met by the same rewards.
  EXPECT_EQ(manager.lessons().at("height"), 1);
  EXPECT_EQ(manager.lesson_names().at("height"), "Mid");
  EXPECT_EQ(manager.sample(1).at("height"), 4.f);
  // The reward buffer starts over: "Mid" waits for its own episodes.
  EXPECT_TRUE(manager.reward_buffer("Jumper").empty());
  EXPECT_FALSE(manager.update(kJumperProgress).changed);
  manager.add_episode_reward("Jumper", 1.0);
  manager.add_episode_reward("Jumper", 1.0);
  EXPECT_TRUE(manager.update(kJumperProgress).changed);
  EXPECT_EQ(manager.lessons().at("height"), 2);
  // The last lesson never ends.
  manager.add_episode_reward("Jumper", 100.0);
  manager.add_episode_reward("Jumper", 100.0);
  EXPECT_FALSE(manager.update(kJumperProgress).changed);
  EXPECT_EQ(manager.lessons().at("height"), 2);
}

TEST(EnvironmentParameterManagerTest, RewardBufferKeepsTheNewestEpisodes) {
  EnvironmentParameterManager manager = three_lessons(3, 5.0);
  for (double reward : {10.0, 1.0, 2.0, 3.0}) manager.add_episode_reward("Jumper", reward);
  EXPECT_EQ(manager.reward_buffer("Jumper"), (std::vector<double>{1.0, 2.0, 3.0}));
  EXPECT_FALSE(manager.update(kJumperProgress).changed);  // mean 2 (the 10 was dropped)
  manager.add_episode_reward("Jumper", NAN);              // not recorded
  manager.add_episode_reward("Other", 7.0);               // no criteria measures it
  EXPECT_EQ(manager.reward_buffer("Jumper"), (std::vector<double>{1.0, 2.0, 3.0}));
  EXPECT_TRUE(manager.reward_buffer("Other").empty());
}

TEST(EnvironmentParameterManagerTest, MinLessonLengthZeroNeedsOneEpisodeForReward) {
  EnvironmentParameterManager manager = three_lessons(0, 0.5);
  EXPECT_EQ(manager.reward_buffer_capacity("Jumper"), 1);
  EXPECT_FALSE(manager.update(kJumperProgress).changed);  // no episode: no mean
  manager.add_episode_reward("Jumper", 1.0);
  EXPECT_TRUE(manager.update(kJumperProgress).changed);
}

TEST(EnvironmentParameterManagerTest, BehaviorWithoutTrainerDoesNotAdvance) {
  EnvironmentParameterManager manager = three_lessons(1, 0.5);
  manager.add_episode_reward("Jumper", 1.0);
  EXPECT_FALSE(manager.update({{"Someone", {1, 10}}}).changed);
  EXPECT_TRUE(manager.update(kJumperProgress).changed);
}

TEST(EnvironmentParameterManagerTest, ProgressMeasure) {
  CompletionCriteria criteria;
  criteria.behavior = "Walker";
  criteria.measure = CompletionMeasure::kProgress;
  criteria.threshold = 0.25;
  criteria.min_lesson_length = 1;
  criteria.require_reset = true;
  EnvironmentParameterManager manager(
      {{"speed", curriculum({lesson("Slow", 1.f, criteria), lesson("Fast", 2.f)})}});
  manager.add_episode_reward("Walker", -100.0);                     // the reward does not matter
  EXPECT_FALSE(manager.update({{"Walker", {250, 1000}}}).changed);  // 0.25 is not > 0.25
  const LessonUpdate update = manager.update({{"Walker", {251, 1000}}});
  EXPECT_TRUE(update.changed);
  EXPECT_TRUE(update.require_reset);
  EXPECT_EQ(manager.lesson_names().at("speed"), "Fast");
  EXPECT_EQ(manager.smoothed_value("speed"), 0.0);  // progress does not smooth
}

TEST(EnvironmentParameterManagerTest, ProgressMeasureStillWaitsForMinLessonLength) {
  CompletionCriteria criteria;
  criteria.behavior = "Walker";
  criteria.measure = CompletionMeasure::kProgress;
  criteria.threshold = 0.1;
  criteria.min_lesson_length = 2;
  EnvironmentParameterManager manager(
      {{"speed", curriculum({lesson("Slow", 1.f, criteria), lesson("Fast", 2.f)})}});
  manager.add_episode_reward("Walker", 0.0);
  EXPECT_FALSE(manager.update({{"Walker", {900, 1000}}}).changed);
  manager.add_episode_reward("Walker", 0.0);
  EXPECT_TRUE(manager.update({{"Walker", {900, 1000}}}).changed);
}

TEST(EnvironmentParameterManagerTest, SmoothingArithmetic) {
  EnvironmentParameterManager manager = three_lessons(2, 0.7, /*smoothing=*/true);
  manager.add_episode_reward("Jumper", 0.5);
  manager.add_episode_reward("Jumper", 1.5);  // mean 1.0
  // 0.25 * 0 + 0.75 * 1.0 = 0.75 > 0.7: advances, and the smoothed value is kept
  EXPECT_TRUE(manager.update(kJumperProgress).changed);
  EXPECT_DOUBLE_EQ(manager.smoothed_value("height"), 0.75);
}

TEST(EnvironmentParameterManagerTest, SmoothingSequence) {
  EnvironmentParameterManager manager = three_lessons(1, 0.95, /*smoothing=*/true);
  manager.add_episode_reward("Jumper", 1.0);
  EXPECT_FALSE(manager.update(kJumperProgress).changed);
  EXPECT_DOUBLE_EQ(manager.smoothed_value("height"), 0.75);
  EXPECT_FALSE(manager.update(kJumperProgress).changed);
  EXPECT_DOUBLE_EQ(manager.smoothed_value("height"), 0.25 * 0.75 + 0.75);  // 0.9375
  EXPECT_TRUE(manager.update(kJumperProgress).changed);  // 0.25 * 0.9375 + 0.75 = 0.984375
  EXPECT_DOUBLE_EQ(manager.smoothed_value("height"), 0.984375);
  // Without smoothing the plain mean decides.
  EnvironmentParameterManager plain = three_lessons(1, 0.95);
  plain.add_episode_reward("Jumper", 1.0);
  EXPECT_TRUE(plain.update(kJumperProgress).changed);
  EXPECT_EQ(plain.smoothed_value("height"), 0.0);
}

TEST(EnvironmentParameterManagerTest, ParametersAdvanceIndependentlyAndClearAllBuffers) {
  EnvironmentParameterManager manager(
      {{"a", curriculum({lesson("A0", 0.f, reward_criteria("Jumper", 0.5, 1)), lesson("A1", 1.f)})},
       {"b", curriculum({lesson("B0", 0.f, reward_criteria("Runner", 0.5, 2)), lesson("B1", 1.f)})},
       {"c", 3.f}});
  manager.add_episode_reward("Jumper", 1.0);
  manager.add_episode_reward("Runner", 1.0);
  const std::map<std::string, BehaviorProgress> progress = {{"Jumper", {1, 10}},
                                                            {"Runner", {1, 10}}};
  EXPECT_TRUE(manager.update(progress).changed);
  EXPECT_EQ(manager.lessons(), (std::map<std::string, int>{{"a", 1}, {"b", 0}}));
  // As in ML-Agents, a lesson change clears every behavior's buffer.
  EXPECT_TRUE(manager.reward_buffer("Runner").empty());
  EXPECT_EQ(manager.sample(1), (Parameters{{"a", 1.f}, {"b", 0.f}, {"c", 3.f}}));
}

TEST(EnvironmentParameterManagerTest, UniformStaysInItsRange) {
  EnvironmentParameterManager manager({{"x", sampled(SamplerSettings::uniform(-2.f, 3.f))}});
  std::mt19937_64 rng(7);
  double sum = 0;
  const int n = 20000;
  for (int i = 0; i < n; ++i) {
    const float x = manager.sample(rng).at("x");
    ASSERT_GE(x, -2.f);
    ASSERT_LE(x, 3.f);
    sum += x;
  }
  EXPECT_NEAR(sum / n, 0.5, 0.05);
}

TEST(EnvironmentParameterManagerTest, GaussianMoments) {
  EnvironmentParameterManager manager({{"x", sampled(SamplerSettings::gaussian(5.f, 2.f))}});
  std::mt19937_64 rng(11);
  const int n = 50000;
  double sum = 0, sum_squares = 0;
  for (int i = 0; i < n; ++i) {
    const double x = manager.sample(rng).at("x");
    sum += x;
    sum_squares += x * x;
  }
  const double mean = sum / n;
  const double stddev = std::sqrt(sum_squares / n - mean * mean);
  EXPECT_NEAR(mean, 5.0, 0.05);  // standard error 2 / sqrt(50000) = 0.009
  EXPECT_NEAR(stddev, 2.0, 0.05);
}

TEST(EnvironmentParameterManagerTest, MultiRangeUniformOnlyInsideItsIntervals) {
  EnvironmentParameterManager manager(
      {{"x", sampled(SamplerSettings::multi_range_uniform({{0.f, 1.f}, {5.f, 8.f}}))}});
  std::mt19937_64 rng(3);
  const int n = 20000;
  int in_second = 0;
  for (int i = 0; i < n; ++i) {
    const float x = manager.sample(rng).at("x");
    const bool first = x >= 0.f && x <= 1.f;
    const bool second = x >= 5.f && x <= 8.f;
    ASSERT_TRUE(first || second) << x;
    in_second += second;
  }
  EXPECT_NEAR(double(in_second) / n, 0.75, 0.02);  // proportional to the lengths 1 and 3

  EnvironmentParameterManager points(
      {{"x", sampled(SamplerSettings::multi_range_uniform({{2.f, 2.f}, {4.f, 4.f}}))}});
  for (int i = 0; i < 100; ++i) {
    const float x = points.sample(rng).at("x");
    ASSERT_TRUE(x == 2.f || x == 4.f) << x;
  }
}

TEST(EnvironmentParameterManagerTest, SameSeedSameDraws) {
  const std::map<std::string, EnvironmentParameterSettings> settings = {
      {"u", sampled(SamplerSettings::uniform(0.f, 1.f))},
      {"g", sampled(SamplerSettings::gaussian(0.f, 1.f))},
      {"m", sampled(SamplerSettings::multi_range_uniform({{0.f, 1.f}, {2.f, 3.f}}))},
      {"c", 4.f}};
  EnvironmentParameterManager a(settings), b(settings);
  std::mt19937_64 rng_a(99), rng_b(99);
  for (int i = 0; i < 50; ++i) ASSERT_EQ(a.sample(rng_a), b.sample(rng_b));
  EXPECT_EQ(a.sample(uint64_t{5}), b.sample(uint64_t{5}));
  EXPECT_NE(a.sample(uint64_t{5}), a.sample(uint64_t{6}));
  // Draws per sample: uniform 1, gaussian 2, multirangeuniform 1, constant 0.
  std::mt19937_64 counted(1), reference(1);
  a.sample(counted);
  reference.discard(4);
  EXPECT_EQ(counted(), reference());
}

TEST(EnvironmentParameterManagerTest, CurriculumLessonSamplerIsDrawn) {
  Lesson first = lesson("Wide", 0.f, reward_criteria("Jumper", 0.5, 1));
  first.value = SamplerSettings::uniform(10.f, 20.f);
  EnvironmentParameterManager manager({{"x", curriculum({first, lesson("Fixed", 1.f)})}});
  std::mt19937_64 rng(1);
  for (int i = 0; i < 100; ++i) {
    const float x = manager.sample(rng).at("x");
    ASSERT_GE(x, 10.f);
    ASSERT_LE(x, 20.f);
  }
}

// Runs `episodes` rewards through a manager, updating after each, and returns the lessons seen.
std::vector<int> drive(EnvironmentParameterManager* manager, const std::vector<double>& rewards,
                       int64_t* steps) {
  std::vector<int> lessons;
  for (const double reward : rewards) {
    manager->add_episode_reward("Jumper", reward);
    *steps += 10;
    manager->update({{"Jumper", {*steps, 1000}}});
    lessons.push_back(manager->lessons().at("height"));
  }
  return lessons;
}

TEST(EnvironmentParameterManagerTest, SerializeThenContinueGivesTheSameLessons) {
  std::vector<double> rewards;
  for (int i = 0; i < 60; ++i) rewards.push_back(0.1 * (i % 7) + 0.006 * i);
  const std::vector<double> head(rewards.begin(), rewards.begin() + 31);
  const std::vector<double> tail(rewards.begin() + 31, rewards.end());

  EnvironmentParameterManager straight = three_lessons(4, 0.55, /*smoothing=*/true);
  int64_t steps = 0;
  std::vector<int> expected = drive(&straight, rewards, &steps);
  ASSERT_EQ(expected.back(), 2) << "the reference run should pass through every lesson";

  EnvironmentParameterManager first = three_lessons(4, 0.55, /*smoothing=*/true);
  steps = 0;
  std::vector<int> seen = drive(&first, head, &steps);
  // The state carried over is not trivial: a lesson passed, rewards and smoothing under way.
  ASSERT_EQ(first.lessons().at("height"), 1);
  ASSERT_FALSE(first.reward_buffer("Jumper").empty());
  ASSERT_NE(first.smoothed_value("height"), 0.0);
  const std::string state = first.serialize();
  EnvironmentParameterManager resumed = three_lessons(4, 0.55, /*smoothing=*/true);
  resumed.deserialize(state);
  EXPECT_EQ(resumed.lessons(), first.lessons());
  EXPECT_EQ(resumed.smoothed_value("height"), first.smoothed_value("height"));  // bit for bit
  EXPECT_EQ(resumed.reward_buffer("Jumper"), first.reward_buffer("Jumper"));
  EXPECT_EQ(resumed.serialize(), state);
  const std::vector<int> rest = drive(&resumed, tail, &steps);
  seen.insert(seen.end(), rest.begin(), rest.end());
  EXPECT_EQ(seen, expected);
  EXPECT_EQ(resumed.serialize(), straight.serialize());
}

TEST(EnvironmentParameterManagerTest, SerializedStateShape) {
  EnvironmentParameterManager manager = three_lessons(2, 0.5, /*smoothing=*/true);
  manager.add_episode_reward("Jumper", 0.25);
  manager.add_episode_reward("Jumper", 0.75);
  EXPECT_FALSE(manager.update(kJumperProgress).changed);  // 0.75 * 0.5 = 0.375
  manager.add_episode_reward("Jumper", 1e-7);
  EXPECT_EQ(manager.serialize(),
            "{\"parameters\": {\"height\": {\"lesson\": 0, \"lesson_name\": \"Low\", "
            "\"smoothed_value\": 0.375, \"furthest_lesson\": 0}}, \"reward_buffers\": "
            "{\"Jumper\": [0.75, 1e-07]}}");
}

TEST(EnvironmentParameterManagerTest, DeserializeChecksTheState) {
  EnvironmentParameterManager manager = three_lessons(2, 0.5);
  EXPECT_THROW(manager.deserialize("[1, 2"), std::runtime_error);
  EXPECT_THROW(manager.deserialize("[1, 2]"), std::runtime_error);
  EXPECT_THROW(manager.deserialize("{\"parameters\": {\"height\": {\"lesson\": 3}}}"),
               std::runtime_error);
  EXPECT_THROW(manager.deserialize("{\"parameters\": {\"height\": {\"lesson\": 1.5}}}"),
               std::runtime_error);
  EXPECT_THROW(manager.deserialize("{\"reward_buffers\": {\"Jumper\": [\"x\"]}}"),
               std::runtime_error);
  // a lesson that the config now names otherwise: its curriculum changed since
  try {
    manager.deserialize(
        "{\"parameters\": {\"height\": {\"lesson\": 1, \"lesson_name\": \"Two\"}}}");
    ADD_FAILURE() << "resumed in a renamed lesson";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("lesson 1 'Two', which the config calls 'Mid'"),
              std::string::npos)
        << e.what();
  }
  manager.deserialize(
      "{\"parameters\": {\"height\": {\"lesson\": 1, \"lesson_name\": \"Mid\"}}}");
  EXPECT_EQ(manager.lessons().at("height"), 1);
  manager.deserialize("{}");
  EXPECT_EQ(manager.lessons().at("height"), 0);
  // Unknown parameters and behaviors are ignored; missing ones start over.
  manager.deserialize(
      "{\"parameters\": {\"gone\": {\"lesson\": 4}, \"height\": {\"lesson\": 2}}, "
      "\"reward_buffers\": {\"Nobody\": [1], \"Jumper\": [1, 2, 3]}}");
  EXPECT_EQ(manager.lessons().at("height"), 2);
  EXPECT_EQ(manager.reward_buffer("Jumper"), (std::vector<double>{2, 3}));  // capacity 2
  manager.deserialize("{}");
  EXPECT_EQ(manager.lessons().at("height"), 0);
  EXPECT_TRUE(manager.reward_buffer("Jumper").empty());
}

// Two lessons of `offset` measured on the env's episode metric "fort_rate", and a second
// parameter measured on the reward of "Jumper".
EnvironmentParameterManager metric_lessons(int min_lesson_length, double threshold) {
  CompletionCriteria forts;
  forts.measure = CompletionMeasure::kMetric;
  forts.metric = "fort_rate";
  forts.threshold = threshold;
  forts.min_lesson_length = min_lesson_length;
  forts.signal_smoothing = false;
  return EnvironmentParameterManager(
      {{"offset", curriculum({lesson("Near", 0.f, forts), lesson("Far", 1.f)})},
       {"height", curriculum({lesson("Low", 0.f, reward_criteria("Jumper", 100.0, 1)),
                              lesson("High", 8.f)})}});
}

TEST(EnvironmentParameterManagerTest, MetricMeasureAdvancesOnTheEpisodeMetric) {
  EnvironmentParameterManager manager = metric_lessons(3, 0.5);
  // rewards do not move a metric lesson, whatever their size
  for (int i = 0; i < 5; ++i) manager.add_episode_reward("Jumper", 50.0);
  manager.add_episode_metrics({{"fort_rate", 1.f}, {"tag_rate", 1.f}});
  manager.add_episode_metrics({{"fort_rate", 1.f}});
  EXPECT_FALSE(manager.update({}).changed);  // 2 episodes < min_lesson_length 3
  manager.add_episode_metrics({{"fort_rate", 0.f}, {"tag_rate", 1.f}});
  manager.add_episode_metrics({{"tag_rate", 1.f}});          // no fort_rate: not counted
  manager.add_episode_metrics({{"fort_rate", float(NAN)}});  // not finite: not counted
  EXPECT_EQ(manager.metric_buffer("fort_rate"), (std::vector<double>{1, 1, 0}));
  EXPECT_TRUE(manager.metric_buffer("tag_rate").empty());  // no criterion measures it
  // no trainer is needed: the metric belongs to the env's episodes
  EXPECT_TRUE(manager.update({}).changed);  // mean 2/3 > 0.5
  EXPECT_EQ(manager.lessons().at("offset"), 1);
  EXPECT_EQ(manager.lessons().at("height"), 0);
  EXPECT_TRUE(manager.metric_buffer("fort_rate").empty());  // every buffer starts over
  EXPECT_TRUE(manager.reward_buffer("Jumper").empty());
}

// A metric criterion that names a behavior counts only the episodes that behavior learned from
// throughout (in self-play, those of its own turns); one that names none counts every episode.
TEST(EnvironmentParameterManagerTest, MetricCriteriaNamingABehaviorCountItsEpisodesOnly) {
  CompletionCriteria hiders;
  hiders.behavior = "Hider";
  hiders.measure = CompletionMeasure::kMetric;
  hiders.metric = "fort_rate";
  hiders.threshold = 0.5;
  hiders.min_lesson_length = 2;
  hiders.signal_smoothing = false;
  CompletionCriteria anyone = hiders;
  anyone.behavior.clear();
  anyone.min_lesson_length = 10;  // its buffer keeps the last 10
  EnvironmentParameterManager manager(
      {{"level", curriculum({lesson("One", 1.f, hiders), lesson("Two", 2.f, anyone),
                             lesson("Three", 3.f)})}});
  manager.add_episode_metrics({{"fort_rate", 1.f}}, {"Hider"});
  manager.add_episode_metrics({{"fort_rate", 0.f}}, {"Seeker"});  // the seekers' turn
  manager.add_episode_metrics({{"fort_rate", 0.f}});              // turns changed during it
  EXPECT_EQ(manager.metric_buffer("fort_rate", "Hider"), (std::vector<double>{1}));
  EXPECT_EQ(manager.metric_buffer("fort_rate"), (std::vector<double>{1, 0, 0}));
  EXPECT_FALSE(manager.update({}).changed);  // one of the hiders' episodes < min_lesson_length 2
  manager.add_episode_metrics({{"fort_rate", 1.f}}, {"Seeker", "Hider"});
  // counted over every episode, {1, 0, 0, 1} would not pass 0.5; the hiders' {1, 1} does
  EXPECT_TRUE(manager.update({}).changed);
  EXPECT_EQ(manager.lesson_names().at("level"), "Two");
  // the state carries the behavior's buffer over a resume
  manager.add_episode_metrics({{"fort_rate", 0.25f}}, {"Hider"});
  EnvironmentParameterManager resumed(manager.settings());
  resumed.deserialize(manager.serialize());
  EXPECT_EQ(resumed.metric_buffer("fort_rate", "Hider"), (std::vector<double>{0.25}));
  EXPECT_EQ(resumed.metric_buffer("fort_rate"), (std::vector<double>{0.25}));
}

// a lesson's other_parameters are set with its own value and change with the lesson
TEST(EnvironmentParameterManagerTest, LessonsSetTheirOtherParameters) {
  Lesson first = lesson("One", 1.f, reward_criteria("Jumper", 0.5, 1));
  first.other_parameters["offset"] = SamplerSettings::constant(0.f);
  Lesson second = lesson("Two", 2.f);
  second.other_parameters["offset"] = SamplerSettings::constant(0.25f);
  EnvironmentParameterManager manager({{"level", curriculum({first, second})}});
  EXPECT_EQ(manager.sample(1), (Parameters{{"level", 1.f}, {"offset", 0.f}}));
  manager.add_episode_reward("Jumper", 1.0);
  ASSERT_TRUE(manager.update(kJumperProgress).changed);
  EXPECT_EQ(manager.sample(1), (Parameters{{"level", 2.f}, {"offset", 0.25f}}));
}

// behavior_max_steps holds from its lesson on and never lowers a behavior's own budget
TEST(EnvironmentParameterManagerTest, LessonsRaiseStepBudgetsFromTheirLessonOn) {
  Lesson one = lesson("One", 1.f, reward_criteria("Jumper", 0.5, 1));
  Lesson two = lesson("Two", 2.f, reward_criteria("Jumper", 0.5, 1));
  two.behavior_max_steps = {{"Flyer", 5000}, {"Jumper", 50}};
  Lesson three = lesson("Three", 3.f);
  EnvironmentParameterManager manager({{"level", curriculum({one, two, three})}});
  EXPECT_EQ(manager.max_steps("Flyer", 1000), 1000);
  manager.add_episode_reward("Jumper", 1.0);
  ASSERT_TRUE(manager.update(kJumperProgress).changed);
  EXPECT_EQ(manager.max_steps("Flyer", 1000), 5000);
  EXPECT_EQ(manager.max_steps("Flyer", 8000), 8000);
  EXPECT_EQ(manager.max_steps("Jumper", 1000), 1000);
  EXPECT_EQ(manager.max_steps("Walker", 1000), 1000);
  manager.add_episode_reward("Jumper", 1.0);
  ASSERT_TRUE(manager.update(kJumperProgress).changed);
  EXPECT_EQ(manager.lesson_names().at("level"), "Three");
  EXPECT_EQ(manager.max_steps("Flyer", 1000), 5000);
  // a resumed manager gives the same budgets
  EnvironmentParameterManager resumed({{"level", curriculum({one, two, three})}});
  resumed.deserialize(manager.serialize());
  EXPECT_EQ(resumed.max_steps("Flyer", 1000), 5000);
}

TEST(EnvironmentParameterManagerTest, MetricMeasureWaitsAtOrBelowItsThreshold) {
  EnvironmentParameterManager manager = metric_lessons(4, 0.5);
  for (float fort : {1.f, 0.f, 1.f, 0.f, 0.f}) manager.add_episode_metrics({{"fort_rate", fort}});
  EXPECT_EQ(manager.metric_buffer("fort_rate"), (std::vector<double>{0, 1, 0, 0}));  // newest 4
  EXPECT_FALSE(manager.update({}).changed);
  manager.add_episode_metrics({{"fort_rate", 1.f}});  // {1, 0, 0, 1}: mean 0.5, not above
  EXPECT_FALSE(manager.update({}).changed);
  manager.add_episode_metrics({{"fort_rate", 1.f}});  // {0, 0, 1, 1} is still 0.5
  EXPECT_FALSE(manager.update({}).changed);
  manager.add_episode_metrics({{"fort_rate", 1.f}});  // {0, 1, 1, 1}
  EXPECT_TRUE(manager.update({}).changed);
}

TEST(EnvironmentParameterManagerTest, MetricNamesAreCheckedAgainstTheEnv) {
  EnvironmentParameterManager manager = metric_lessons(1, 0.5);
  EXPECT_NO_THROW(manager.check_metric_names({"fort_rate", "tag_rate"}));
  try {
    manager.check_metric_names({"tag_rate", "seen_fraction"});
    FAIL() << "a metric the env does not report must be an error";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(),
                 "environment_parameters.offset, lesson 'Near': completion_criteria measures the "
                 "episode metric 'fort_rate', which the environment does not report (it "
                 "reports: tag_rate, seen_fraction)");
  }
  EXPECT_THROW(manager.check_metric_names({}), std::invalid_argument);
  EXPECT_NO_THROW(three_lessons(1, 0.5).check_metric_names({}));  // nothing measures a metric
}

// Three lessons of `height` on the Jumper's reward, the first of which also waits for the
// strategy "chasing" to emerge.
EnvironmentParameterManager lessons_after_chasing(bool smoothing) {
  CompletionCriteria waits = reward_criteria("Jumper", 0.7, 1, smoothing);
  waits.after_emerged = {"chasing"};
  return EnvironmentParameterManager(
      {{"height", curriculum({lesson("Low", 0.f, waits),
                              lesson("Mid", 4.f, reward_criteria("Jumper", 0.7, 1, smoothing)),
                              lesson("High", 8.f)})}});
}

TEST(EnvironmentParameterManagerTest, ALessonAfterAStrategyWaitsForItToEmerge) {
  EnvironmentParameterManager manager = lessons_after_chasing(/*smoothing=*/false);
  manager.add_episode_reward("Jumper", 1.0);
  // met, but "chasing" has not emerged (another strategy has): the lesson goes on, said once
  LessonUpdate update = manager.update(kJumperProgress, {"shelter"});
  EXPECT_FALSE(update.changed);
  EXPECT_EQ(manager.lessons().at("height"), 0);
  ASSERT_EQ(update.waits.size(), 1u);
  EXPECT_EQ(update.waits[0],
            "Curriculum height: lesson 0 (Low) met its threshold and goes on until the strategy "
            "chasing has emerged (after_emerged)");
  EXPECT_TRUE(manager.update(kJumperProgress, {"shelter"}).waits.empty());
  EXPECT_EQ(manager.reward_buffer("Jumper"), (std::vector<double>{1.0}));  // nothing cleared
  // emerged: the lesson ends on the episodes it already has
  update = manager.update(kJumperProgress, {"shelter", "chasing"});
  EXPECT_TRUE(update.changed);
  EXPECT_TRUE(update.waits.empty());
  EXPECT_EQ(manager.lessons().at("height"), 1);
  // the next lesson does not wait for anything
  manager.add_episode_reward("Jumper", 1.0);
  EXPECT_TRUE(manager.update(kJumperProgress).changed);
  EXPECT_EQ(manager.lessons().at("height"), 2);
}

TEST(EnvironmentParameterManagerTest, AStrategyThatEmergedFirstChangesNothing) {
  // the control: with the strategy emerged from the start, the lessons and smoothed values move
  // update for update as they do with no after_emerged at all
  EnvironmentParameterManager waits = lessons_after_chasing(/*smoothing=*/true);
  EnvironmentParameterManager plain = three_lessons(1, 0.7, /*smoothing=*/true);
  for (const double reward : {0.5, 0.9, 0.2, 1.0, 1.0, 0.8, 1.0}) {
    waits.add_episode_reward("Jumper", reward);
    plain.add_episode_reward("Jumper", reward);
    const LessonUpdate a = waits.update(kJumperProgress, {"chasing"});
    const LessonUpdate b = plain.update(kJumperProgress);
    EXPECT_EQ(a.changed, b.changed);
    EXPECT_EQ(waits.lessons(), plain.lessons());
    EXPECT_DOUBLE_EQ(waits.smoothed_value("height"), plain.smoothed_value("height"));
  }
  EXPECT_EQ(plain.lessons().at("height"), 2);
}

TEST(EnvironmentParameterManagerTest, StrategyNamesAreCheckedAgainstTheEnv) {
  EnvironmentParameterManager manager = lessons_after_chasing(false);
  EXPECT_NO_THROW(manager.check_strategy_names({"shelter", "chasing"}));
  try {
    manager.check_strategy_names({"running_and_chasing", "shelter"});
    FAIL() << "a strategy the env does not declare must be an error";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(),
                 "environment_parameters.height, lesson 'Low': completion_criteria.after_emerged "
                 "names the strategy 'chasing', which the environment does not declare (it "
                 "declares: running_and_chasing, shelter)");
  }
  EXPECT_THROW(manager.check_strategy_names({}), std::invalid_argument);
  EXPECT_NO_THROW(three_lessons(1, 0.5).check_strategy_names({}));  // nothing waits
}

TEST(EnvironmentParameterManagerTest, MetricBuffersSurviveAResume) {
  EnvironmentParameterManager manager = metric_lessons(3, 0.9);
  manager.add_episode_metrics({{"fort_rate", 1.f}});
  manager.add_episode_metrics({{"fort_rate", 0.25f}});
  manager.add_episode_reward("Jumper", 2.0);
  const std::string state = manager.serialize();
  EXPECT_NE(state.find("\"metric_buffers\": {\"fort_rate\": [1, 0.25]}"), std::string::npos)
      << state;
  EnvironmentParameterManager resumed = metric_lessons(3, 0.9);
  resumed.deserialize(state);
  EXPECT_EQ(resumed.metric_buffer("fort_rate"), (std::vector<double>{1, 0.25}));
  EXPECT_EQ(resumed.serialize(), state);
  EXPECT_THROW(resumed.deserialize("{\"metric_buffers\": {\"fort_rate\": 3}}"), std::runtime_error);
  EXPECT_EQ(resumed.metric_buffer("fort_rate"), (std::vector<double>{1, 0.25}));  // unchanged
  // a state written before metric buffers existed reads as empty ones
  resumed.deserialize("{\"reward_buffers\": {\"Jumper\": [2]}}");
  EXPECT_TRUE(resumed.metric_buffer("fort_rate").empty());
}

TEST(EnvironmentParameterManagerTest, EmptyManager) {
  EnvironmentParameterManager manager;
  EXPECT_TRUE(manager.empty());
  EXPECT_TRUE(manager.sample(1).empty());
  EXPECT_FALSE(manager.update({}).changed);
  EnvironmentParameterManager restored;
  restored.deserialize(manager.serialize());
  EXPECT_TRUE(restored.lessons().empty());
}

}  // namespace
}  // namespace rlt

namespace rlt {
namespace {

// Three lessons of `offset` measured on "fort_rate" (threshold 0.5 over 2 episodes, no
// smoothing) that fall back when the mean of the last 3 episodes is at or below 0.25.
EnvironmentParameterManager falling_lessons() {
  CompletionCriteria forts;
  forts.measure = CompletionMeasure::kMetric;
  forts.metric = "fort_rate";
  forts.threshold = 0.5;
  forts.min_lesson_length = 2;
  forts.signal_smoothing = false;
  forts.fallback_threshold = 0.25;
  forts.fallback_length = 3;
  Lesson near = lesson("Near", 0.f, forts), mid = lesson("Mid", 0.5f, forts),
         far = lesson("Far", 1.f, forts);
  mid.behavior_max_steps = {{"Seeker", 500}};
  return EnvironmentParameterManager({{"offset", curriculum({near, mid, far})}});
}

void add_forts(EnvironmentParameterManager* manager, const std::vector<float>& rates) {
  for (const float rate : rates) manager->add_episode_metrics({{"fort_rate", rate}});
}

TEST(EnvironmentParameterManagerTest, ACollapsedLessonFallsBackOneLesson) {
  EnvironmentParameterManager manager = falling_lessons();
  add_forts(&manager, {1.f, 1.f});
  LessonUpdate update = manager.update({});  // Near -> Mid
  ASSERT_TRUE(update.changed);
  ASSERT_EQ(update.changes.size(), 1u);
  EXPECT_EQ(update.changes[0].parameter, "offset");
  EXPECT_EQ(update.changes[0].from, 0);
  EXPECT_EQ(update.changes[0].to, 1);
  EXPECT_FALSE(update.changes[0].fell_back);
  EXPECT_DOUBLE_EQ(update.changes[0].measure, 1.0);  // the mean that passed the threshold
  // two bad episodes are not yet the three the fallback judges; the completion needs > 0.5
  add_forts(&manager, {0.f, 0.f});
  update = manager.update({});
  EXPECT_FALSE(update.changed);
  EXPECT_TRUE(update.fallbacks.empty());
  EXPECT_TRUE(update.changes.empty());
  // the third: mean 0 over the last 3 <= 0.25
  add_forts(&manager, {0.f});
  update = manager.update({});
  EXPECT_TRUE(update.changed);
  EXPECT_FALSE(update.require_reset);
  ASSERT_EQ(update.changes.size(), 1u);
  EXPECT_EQ(update.changes[0].from, 1);
  EXPECT_EQ(update.changes[0].to, 0);
  EXPECT_TRUE(update.changes[0].fell_back);
  EXPECT_DOUBLE_EQ(update.changes[0].measure, 0.0);
  ASSERT_EQ(update.fallbacks.size(), 1u);
  EXPECT_NE(update.fallbacks[0].find("offset: back from lesson 1 (Mid) to 0 (Near): mean "
                                     "fort_rate 0 over the last 3 episodes"),
            std::string::npos)
      << update.fallbacks[0];
  EXPECT_EQ(manager.lessons().at("offset"), 0);
  EXPECT_TRUE(manager.metric_buffer("fort_rate").empty());
  // the first lesson never falls back
  add_forts(&manager, {0.f, 0.f, 0.f});
  EXPECT_FALSE(manager.update({}).changed);
  // the furthest lesson keeps its step budget and survives a resume
  EXPECT_EQ(manager.furthest_lessons().at("offset"), 1);
  EXPECT_EQ(manager.max_steps("Seeker", 100), 500);
  EnvironmentParameterManager resumed = falling_lessons();
  resumed.deserialize(manager.serialize());
  EXPECT_EQ(resumed.lessons().at("offset"), 0);
  EXPECT_EQ(resumed.furthest_lessons().at("offset"), 1);
  EXPECT_EQ(resumed.max_steps("Seeker", 100), 500);
}

TEST(EnvironmentParameterManagerTest, FallbackJudgesOnlyTheLastEpisodesAboveItsThreshold) {
  EnvironmentParameterManager manager = falling_lessons();
  add_forts(&manager, {1.f, 1.f});
  ASSERT_TRUE(manager.update({}).changed);
  // 0.375 over the last three (above 0.25), though the lesson's first episodes were worse
  add_forts(&manager, {0.f, 0.f, 0.f, 0.375f, 0.375f, 0.375f});
  // (the completion mean over its buffer of 2 is 0.375: no advance either)
  EXPECT_FALSE(manager.update({}).changed);
  EXPECT_EQ(manager.lessons().at("offset"), 1);
  // exactly at the threshold falls back
  add_forts(&manager, {0.25f, 0.25f, 0.25f});
  EXPECT_TRUE(manager.update({}).changed);
  EXPECT_EQ(manager.lessons().at("offset"), 0);
}

TEST(EnvironmentParameterManagerTest, TheLastLessonFallsBackAndCompletionIsUnchanged) {
  EnvironmentParameterManager manager = falling_lessons();
  add_forts(&manager, {1.f, 1.f});
  ASSERT_TRUE(manager.update({}).changed);
  add_forts(&manager, {1.f, 1.f});
  ASSERT_TRUE(manager.update({}).changed);
  EXPECT_EQ(manager.lesson_names().at("offset"), "Far");
  // the completion buffer keeps min_lesson_length (2) episodes, not the fallback's 3
  add_forts(&manager, {0.f, 0.f, 0.f});
  EXPECT_EQ(manager.metric_buffer("fort_rate"), (std::vector<double>{0.0, 0.0}));
  EXPECT_TRUE(manager.update({}).changed);
  EXPECT_EQ(manager.lesson_names().at("offset"), "Mid");
  // the control: without fallback_threshold the same episodes leave the lesson alone
  EnvironmentParameterManager plain = three_lessons(2, 0.5);
  plain.add_episode_reward("Jumper", 1.0);
  plain.add_episode_reward("Jumper", 1.0);
  ASSERT_TRUE(plain.update(kJumperProgress).changed);
  for (int i = 0; i < 10; ++i) plain.add_episode_reward("Jumper", -5.0);
  EXPECT_FALSE(plain.update(kJumperProgress).changed);
  EXPECT_EQ(plain.lessons().at("height"), 1);
}

// A level whose first lesson moves `offset` from 0 to 1 by a staircase on the fort rate
// (threshold 0.5: an episode that closed the room goes up 0.25, any other down 0.1), then a
// lesson at the own places.
EnvironmentParameterManager staircase_lessons(int min_lesson_length = 0) {
  CompletionCriteria forts;
  forts.measure = CompletionMeasure::kMetric;
  forts.metric = "fort_rate";
  forts.threshold = 0.5;
  forts.min_lesson_length = min_lesson_length;
  forts.signal_smoothing = false;
  Lesson climb = lesson("Climb", 2.f, forts);
  climb.other_parameters["offset"] = SamplerSettings::constant(0.f);
  climb.staircase = Staircase{"offset", 1.0, 0.25, 0.1};
  Lesson own = lesson("Own", 2.f);
  own.other_parameters["offset"] = SamplerSettings::constant(1.f);
  return EnvironmentParameterManager({{"level", curriculum({climb, own})}});
}

TEST(EnvironmentParameterManagerTest, AStaircaseClimbsOnSuccessAndStepsBackOnFailure) {
  EnvironmentParameterManager manager = staircase_lessons();
  EXPECT_EQ(manager.sample(1).at("offset"), 0.f);  // the lesson's own value first
  add_forts(&manager, {1.f, 1.f});                 // 0.25, 0.5
  EXPECT_DOUBLE_EQ(manager.staircase_values().at("level"), 0.5);
  add_forts(&manager, {0.f, 0.5f});  // at the threshold is no success: 0.4, 0.3
  EXPECT_DOUBLE_EQ(manager.staircase_values().at("level"), 0.3);
  EXPECT_FLOAT_EQ(manager.sample(1).at("offset"), 0.3f);
  EXPECT_FALSE(manager.update({}).changed);  // not at the end yet
  add_forts(&manager, {0.f, 0.f, 0.f, 0.f});  // never below the start
  EXPECT_DOUBLE_EQ(manager.staircase_values().at("level"), 0.0);
  add_forts(&manager, {1.f, 1.f, 1.f, 1.f, 1.f});  // never past the end
  EXPECT_DOUBLE_EQ(manager.staircase_values().at("level"), 1.0);
  // episodes that are not counted (not finite, or without the metric) do not move it
  add_forts(&manager, {float(NAN)});
  manager.add_episode_metrics({{"tag_rate", 0.f}});
  EXPECT_DOUBLE_EQ(manager.staircase_values().at("level"), 1.0);
  // at the end the lesson completes; the next lesson has no staircase
  EXPECT_TRUE(manager.update({}).changed);
  EXPECT_EQ(manager.lesson_names().at("level"), "Own");
  EXPECT_TRUE(manager.staircase_values().empty());
  EXPECT_EQ(manager.sample(1).at("offset"), 1.f);
}

// The control: the same episodes with no staircase leave the offset where the lesson set it.
TEST(EnvironmentParameterManagerTest, WithoutAStaircaseTheLessonsValueStays) {
  EnvironmentParameterManager manager = staircase_lessons();
  EnvironmentParameterSettings settings = manager.settings().at("level");
  settings.curriculum[0].staircase.reset();
  EnvironmentParameterManager plain({{"level", settings}});
  add_forts(&plain, {1.f, 1.f, 1.f, 1.f, 1.f});
  EXPECT_EQ(plain.sample(1).at("offset"), 0.f);
  EXPECT_TRUE(plain.staircase_values().empty());
}

TEST(EnvironmentParameterManagerTest, AStaircaseAtItsEndStillWaitsForMinLessonLength) {
  EnvironmentParameterManager manager = staircase_lessons(6);
  add_forts(&manager, {1.f, 1.f, 1.f, 1.f});
  EXPECT_DOUBLE_EQ(manager.staircase_values().at("level"), 1.0);
  EXPECT_FALSE(manager.update({}).changed);  // 4 episodes < 6
  add_forts(&manager, {1.f, 1.f});
  EXPECT_TRUE(manager.update({}).changed);
}

// A staircase may run downward (end below the start): success moves it toward the end.
TEST(EnvironmentParameterManagerTest, ADownwardStaircaseMovesTowardItsEnd) {
  CompletionCriteria jumps = reward_criteria("Jumper", 10.0, 0);
  Lesson shrink = lesson("Shrink", 8.f, jumps);
  shrink.staircase = Staircase{"height", 2.0, 3.0, 1.0};
  EnvironmentParameterManager manager({{"height", curriculum({shrink, lesson("Low", 2.f)})}});
  manager.add_episode_reward("Jumper", 11.0);  // 5
  manager.add_episode_reward("Jumper", 3.0);   // 6
  EXPECT_FLOAT_EQ(manager.sample(1).at("height"), 6.f);
  manager.add_episode_reward("Jumper", 3.0);  // 7
  manager.add_episode_reward("Jumper", 3.0);  // 8
  manager.add_episode_reward("Jumper", 3.0);  // still 8: never above the start
  manager.add_episode_reward("Jumper", 20.0);
  manager.add_episode_reward("Jumper", 20.0);
  EXPECT_DOUBLE_EQ(manager.staircase_values().at("height"), 2.0);
  EXPECT_TRUE(manager.update(kJumperProgress).changed);
}

TEST(EnvironmentParameterManagerTest, AStaircaseSurvivesAResumeAndFollowsRankZero) {
  EnvironmentParameterManager manager = staircase_lessons();
  add_forts(&manager, {1.f, 1.f, 0.f});  // 0.4
  EnvironmentParameterManager resumed = staircase_lessons();
  resumed.deserialize(manager.serialize());
  EXPECT_DOUBLE_EQ(resumed.staircase_values().at("level"), 0.4);
  add_forts(&manager, {1.f});
  add_forts(&resumed, {1.f});
  EXPECT_EQ(resumed.staircase_values(), manager.staircase_values());
  // a state whose value lies outside the lesson's staircase is refused, the manager unchanged
  std::string state = manager.serialize();
  const std::string value = "\"staircase_value\": 0.65";
  ASSERT_NE(state.find(value), std::string::npos) << state;
  state.replace(state.find(value), value.size(), "\"staircase_value\": 1.5");
  try {
    resumed.deserialize(state);
    FAIL() << "a staircase value of 1.5 was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("parameters.level.staircase_value: 1.5 is outside"),
              std::string::npos)
        << e.what();
  }
  EXPECT_DOUBLE_EQ(resumed.staircase_values().at("level"), 0.65);
  // another rank takes rank 0's value without a lesson change (its buffers stay)
  EnvironmentParameterManager follower = staircase_lessons();
  add_forts(&follower, {0.f});
  EXPECT_FALSE(follower.follow({{"level", 0}}, {{"level", 0.65}}).changed);
  EXPECT_DOUBLE_EQ(follower.staircase_values().at("level"), 0.65);
  EXPECT_EQ(follower.metric_buffer("fort_rate"), (std::vector<double>{0.0}));
  // a follower's own episodes do not move its staircase: only rank 0's values do
  follower.set_staircases_follow_only(true);
  add_forts(&follower, {1.f, 1.f, 0.f});
  EXPECT_DOUBLE_EQ(follower.staircase_values().at("level"), 0.65);
  follower.follow({}, {{"level", 0.8}});
  EXPECT_DOUBLE_EQ(follower.staircase_values().at("level"), 0.8);
  // entering the lesson again starts its staircase over
  follower.follow({{"level", 1}});
  follower.follow({{"level", 0}});
  EXPECT_DOUBLE_EQ(follower.staircase_values().at("level"), 0.0);
}

}  // namespace
}  // namespace rlt
