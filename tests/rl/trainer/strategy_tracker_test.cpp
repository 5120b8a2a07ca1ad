// StrategyTracker: a strategy emerges at the first step where the mean of its metric over a full
// window of qualifying episodes exceeds the threshold, once, dated in its behavior's steps.
#include "rl/trainer/strategy_tracker.h"

#include <gtest/gtest.h>

namespace rlt {
namespace {

StrategySpec chase() { return {"chase", "tag_rate", "Seeker", 0.5f, 4, {}}; }
StrategySpec shelter() { return {"shelter", "fort_rate", "Hider", 0.5f, 2, {{"level", 2.f}}}; }

TEST(StrategyTrackerTest, EmergesWhenTheWindowMeanCrossesTheThreshold) {
  StrategyTracker tracker({chase()});
  auto level = [](const std::string&) { return 1.f; };
  const float tags[] = {1, 1, 1, 0, 0, 1, 1};  // window 4: 0.75 after 4 episodes is the first full
  std::vector<int64_t> emerged_at;
  for (int i = 0; i < 7; ++i) {
    auto e = tracker.add_episode({{"tag_rate", tags[i]}}, level, {{"Seeker", 100 * (i + 1)}}, i);
    if (!e.empty()) emerged_at.push_back(100 * (i + 1));
  }
  ASSERT_EQ(emerged_at.size(), 1u) << "a strategy emerges once";
  EXPECT_EQ(emerged_at[0], 400);
  EXPECT_EQ(tracker.emergences()[0].step, 400);
  EXPECT_DOUBLE_EQ(tracker.emergences()[0].rate, 0.75);
  EXPECT_DOUBLE_EQ(tracker.rate(0), 0.5);  // the last four: 0, 0, 1, 1
}

TEST(StrategyTrackerTest, NeedsAFullWindowAndAboveThreshold) {
  StrategyTracker tracker({chase()});
  auto level = [](const std::string&) { return 1.f; };
  for (int i = 0; i < 3; ++i)
    EXPECT_TRUE(tracker.add_episode({{"tag_rate", 1.f}}, level, {{"Seeker", i}}, 0).empty());
  // exactly 0.5 is not above the threshold
  StrategyTracker half({chase()});
  const float tags[] = {1, 0, 1, 0, 1, 0, 1, 0};
  for (float t : tags) EXPECT_TRUE(half.add_episode({{"tag_rate", t}}, level, {{"Seeker", 1}}, 0).empty());
  EXPECT_EQ(half.emergences()[0].step, -1);
}

TEST(StrategyTrackerTest, OnlyEpisodesMeetingTheConditionCount) {
  StrategyTracker tracker({shelter()});
  float level = 1.f;
  auto parameter = [&](const std::string& name) { return name == "level" ? level : 0.f; };
  for (int i = 0; i < 5; ++i)  // forts at level 1 do not count
    EXPECT_TRUE(tracker.add_episode({{"fort_rate", 1.f}}, parameter, {{"Hider", i}}, 0).empty());
  EXPECT_DOUBLE_EQ(tracker.rate(0), 0.0);
  level = 2.f;
  EXPECT_TRUE(tracker.add_episode({{"fort_rate", 1.f}}, parameter, {{"Hider", 10}}, 0).empty());
  auto e = tracker.add_episode({{"fort_rate", 1.f}}, parameter, {{"Hider", 11}}, 5.0);
  ASSERT_EQ(e.size(), 1u);
  EXPECT_EQ(tracker.emergences()[0].step, 11);
  EXPECT_DOUBLE_EQ(tracker.emergences()[0].elapsed_s, 5.0);
}

TEST(StrategyTrackerTest, EveryConditionMustHold) {
  StrategySpec spec = shelter();
  spec.conditions.push_back({"prop_start_offset", 1.f});
  EXPECT_EQ(spec.describe_conditions(), "level >= 2 and prop_start_offset >= 1");
  StrategyTracker tracker({spec});
  std::map<std::string, float> values = {{"level", 3.f}, {"prop_start_offset", 0.5f}};
  auto parameter = [&](const std::string& name) { return values.at(name); };
  for (int i = 0; i < 5; ++i)  // level 3 but props started half way: no count
    EXPECT_TRUE(tracker.add_episode({{"fort_rate", 1.f}}, parameter, {{"Hider", i}}, 0).empty());
  values["prop_start_offset"] = 1.f;
  values["level"] = 1.f;  // full offset but level 1: no count either
  EXPECT_TRUE(tracker.add_episode({{"fort_rate", 1.f}}, parameter, {{"Hider", 6}}, 0).empty());
  EXPECT_DOUBLE_EQ(tracker.rate(0), 0.0);
  values["level"] = 2.f;
  EXPECT_TRUE(tracker.add_episode({{"fort_rate", 1.f}}, parameter, {{"Hider", 7}}, 0).empty());
  ASSERT_EQ(tracker.add_episode({{"fort_rate", 1.f}}, parameter, {{"Hider", 8}}, 0).size(), 1u);
  EXPECT_EQ(tracker.emergences()[0].step, 8);
}

// a metric of the condition's name wins over the parameter (the env says what the parameter did)
TEST(StrategyTrackerTest, AConditionReadsTheEpisodesMetricFirst) {
  StrategySpec spec = shelter();
  spec.conditions.push_back({"prop_start_offset", 1.f});
  StrategyTracker tracker({spec});
  std::map<std::string, float> values = {{"level", 3.f}, {"prop_start_offset", 0.5f}};
  auto parameter = [&](const std::string& name) { return values.at(name); };
  // the parameter is 0.5 but the env reports that the props started at their places
  tracker.add_episode({{"fort_rate", 1.f}, {"prop_start_offset", 1.f}}, parameter, {{"Hider", 1}},
                      0);
  EXPECT_DOUBLE_EQ(tracker.rate(0), 1.0);
  // and the other way round: a parameter of 1 with a reported 0.2 does not count
  values["prop_start_offset"] = 1.f;
  tracker.add_episode({{"fort_rate", 0.f}, {"prop_start_offset", 0.2f}}, parameter, {{"Hider", 2}},
                      0);
  EXPECT_DOUBLE_EQ(tracker.rate(0), 1.0);
}

TEST(StrategyTrackerTest, EpisodesWithoutTheMetricAreIgnoredAndWindowsRoundTrip) {
  StrategyTracker tracker({chase(), shelter()});
  auto level = [](const std::string&) { return 3.f; };
  tracker.add_episode({{"other", 1.f}}, level, {{"Seeker", 1}, {"Hider", 1}}, 0);
  EXPECT_TRUE(tracker.save_window(0).empty());
  tracker.add_episode({{"tag_rate", 1.f}, {"fort_rate", 0.f}}, level, {{"Seeker", 2}, {"Hider", 2}}, 0);
  StrategyTracker copy({chase(), shelter()});
  copy.load_window(0, tracker.save_window(0));
  copy.load_window(1, tracker.save_window(1));
  EXPECT_DOUBLE_EQ(copy.rate(0), 1.0);
  EXPECT_DOUBLE_EQ(copy.rate(1), 0.0);
}

TEST(StrategyTrackerTest, BadWindowIsAnError) {
  StrategySpec s = chase();
  s.window = 0;
  EXPECT_THROW(StrategyTracker({s}), std::invalid_argument);
}

}  // namespace
}  // namespace rlt
