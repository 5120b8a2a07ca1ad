// `rlt lessons`: the lesson table of a run's episodes.csv, summed by hand here for a self-play
// run with a fallback, a row in which both behaviors learned and a metric cell left empty by a
// resume, and with its lessons.csv's exact changes; then the command as a process on a run
// folder, and its errors (a configuration that cannot be read only leaves the lessons unnamed).
#include "apps/lesson_table.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "tests/apps/shell_command.h"

#ifndef RLT_BINARY
#error "RLT_BINARY must name the rlt executable"
#endif

namespace fs = std::filesystem;

namespace rlt {
namespace {

const double kEmpty = std::nan("");

// Hiders and seekers take turns; lesson 0, then 1, back to 0 (a fallback) and 1 again. Row 4 is
// logged across a change of turns (both behaviors' steps advanced); row 2's hider0_idle is empty.
RunCurves self_play_run() {
  RunCurves run;
  run.behaviors = {"Hider", "Seeker"};
  run.episodes.columns = {"total_steps", "elapsed_s", "episodes",        "Hider_step",
                          "Seeker_step", "lesson_level", "fort_rate", "hider0_idle",
                          "smoothed_fort_rate_shelter"};
  run.episodes.rows = {
      {100, 1, 4, 0, 100, 0, 0.5, 0.2, 0.1},    // the seekers' turn
      {200, 2, 2, 100, 100, 0, 1.0, kEmpty, 0.2},  // the hiders' turn
      {300, 3, 2, 200, 100, 1, 0.0, 0.4, 0.3},  // lesson 1 from hider step 100
      {400, 4, 6, 250, 150, 1, 1.0, 0.9, 0.4},  // both learned: not a hiders' turn
      {500, 5, 2, 350, 150, 0, 0.5, 0.6, 0.5},  // back to lesson 0
      {600, 6, 2, 450, 150, 1, 1.0, 0.0, 0.6},  // lesson 1 again
  };
  return run;
}

TEST(LessonTable, TheHidersTurnsCountTheirStepsAndEpisodesLessonByLesson) {
  const auto table = summarize_lessons(self_play_run(), "level", "Hider", {}, {"first", "second"});
  ASSERT_EQ(table.metrics, (std::vector<std::string>{"fort_rate", "hider0_idle"}));
  ASSERT_EQ(table.lessons.size(), 2u);
  const auto& first = table.lessons[0];
  EXPECT_EQ(first.lesson, 0);
  EXPECT_EQ(first.name, "first");
  EXPECT_EQ(first.entered, 0);
  EXPECT_EQ(first.steps, 0 + 100 + 100);
  EXPECT_EQ(first.visits, 2);
  EXPECT_EQ(first.episodes, 2 + 2);  // rows 2 and 5
  EXPECT_DOUBLE_EQ(first.means[0], (1.0 * 2 + 0.5 * 2) / 4);
  EXPECT_DOUBLE_EQ(first.means[1], 0.6);  // row 2's cell is empty: row 5 alone
  const auto& second = table.lessons[1];
  EXPECT_EQ(second.name, "second");
  EXPECT_EQ(second.entered, 100);
  EXPECT_EQ(second.steps, 100 + 50 + 100);
  EXPECT_EQ(second.visits, 2);
  EXPECT_EQ(second.episodes, 2 + 2);  // rows 3 and 6, not row 4
  EXPECT_DOUBLE_EQ(second.means[0], (0.0 * 2 + 1.0 * 2) / 4);
  EXPECT_DOUBLE_EQ(second.means[1], (0.4 * 2 + 0.0 * 2) / 4);
}

// metrics/lessons.csv for self_play_run(): 0 -> 1 between rows 2 and 3, back to 0 between rows 4
// and 5, then 1, 2 and back to 1 between rows 5 and 6 (lesson 2 has no row); one change of another
// parameter, which does not count
LessonChanges self_play_changes() {
  LessonChanges c;
  c.step_columns = {"total_steps", "Hider_step", "Seeker_step"};
  const auto row = [](double total, double hider, const std::string& parameter, int from, int to,
                      bool back, double measure) {
    LessonChangeRow r;
    r.steps = {total, hider, 100};
    r.parameter = parameter;
    r.from = from;
    r.to = to;
    r.fell_back = back;
    r.measure = measure;
    return r;
  };
  c.rows = {row(260, 160, "level", 0, 1, false, 0.55), row(300, 200, "speed", 0, 1, false, 0.9),
            row(480, 330, "level", 1, 0, true, 0.01),  row(520, 370, "level", 0, 1, false, 0.6),
            row(560, 410, "level", 1, 2, false, 0.8),  row(590, 440, "level", 2, 1, true, 0.0)};
  return c;
}

TEST(LessonTable, TheChangesPlaceEachEntryExactlyAndKeepALessonPassedBetweenSummaries) {
  const auto table = summarize_lessons(self_play_run(), "level", "Hider", {"fort_rate"},
                                       {"first", "second", "third"}, self_play_changes());
  EXPECT_TRUE(table.exact);
  ASSERT_EQ(table.lessons.size(), 3u);
  const auto& first = table.lessons[0];
  EXPECT_EQ(first.entered, 0);
  EXPECT_EQ(first.steps, 160 + (370 - 330));
  EXPECT_EQ(first.visits, 2);
  EXPECT_DOUBLE_EQ(first.completed_at, 0.6);  // its last completion
  EXPECT_EQ(first.episodes, 4);               // the rows' as before
  EXPECT_DOUBLE_EQ(first.means[0], 0.75);
  const auto& second = table.lessons[1];
  EXPECT_EQ(second.entered, 160);
  EXPECT_EQ(second.steps, (330 - 160) + (410 - 370) + (450 - 440));  // to the last row's 450
  EXPECT_EQ(second.visits, 3);
  EXPECT_DOUBLE_EQ(second.completed_at, 0.8);
  const auto& third = table.lessons[2];
  EXPECT_EQ(third.lesson, 2);
  EXPECT_EQ(third.name, "third");
  EXPECT_EQ(third.entered, 410);
  EXPECT_EQ(third.steps, 30);
  EXPECT_EQ(third.visits, 1);
  EXPECT_TRUE(std::isnan(third.completed_at));
  EXPECT_EQ(third.episodes, 0);
  EXPECT_TRUE(std::isnan(third.means[0]));
  const std::string markdown = lesson_table_markdown(table, 2);
  EXPECT_NE(markdown.find("| episodes | completed at | fort_rate |"), std::string::npos) << markdown;
  EXPECT_NE(markdown.find("| 2 | third | 410 | 30 | 1 | 0 | - | - |"), std::string::npos)
      << markdown;
  // on total steps the same changes, the last stretch running to the last row's 600
  const auto total = summarize_lessons(self_play_run(), "level", "", {"fort_rate"}, {},
                                       self_play_changes());
  EXPECT_EQ(total.lessons[1].steps, (480 - 260) + (560 - 520) + (600 - 590));
  // a counter the file does not have is an error naming what it has
  LessonChanges hiders_only = self_play_changes();
  hiders_only.step_columns = {"total_steps", "Hider_step", "Runner_step"};
  try {
    summarize_lessons(self_play_run(), "level", "Seeker", {}, {}, hiders_only);
    ADD_FAILURE() << "no error";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("'Seeker_step' is not in metrics/lessons.csv (it has: "
                                         "total_steps, Hider_step, Runner_step)"),
              std::string::npos)
        << e.what();
  }
}

TEST(LessonTable, WithoutABehaviorEveryRowCountsOnTotalSteps) {
  const auto table = summarize_lessons(self_play_run(), "level", "", {"fort_rate"}, {});
  ASSERT_EQ(table.lessons.size(), 2u);
  EXPECT_EQ(table.lessons[0].name, "");
  EXPECT_EQ(table.lessons[0].steps, 300);
  EXPECT_EQ(table.lessons[0].episodes, 8);
  EXPECT_DOUBLE_EQ(table.lessons[0].means[0], (0.5 * 4 + 1.0 * 2 + 0.5 * 2) / 8);
  EXPECT_EQ(table.lessons[1].entered, 200);
  EXPECT_EQ(table.lessons[1].steps, 300);
  EXPECT_EQ(table.lessons[1].episodes, 10);
  EXPECT_DOUBLE_EQ(table.lessons[1].means[0], (0.0 * 2 + 1.0 * 6 + 1.0 * 2) / 10);
}

TEST(LessonTable, AMetricWithNoCountedEpisodeIsEmptyNotZero) {
  // the seekers' turns are rows 1 only; lesson 1 has none of them
  const auto table = summarize_lessons(self_play_run(), "level", "Seeker", {"fort_rate"}, {});
  ASSERT_EQ(table.lessons.size(), 2u);
  EXPECT_EQ(table.lessons[0].episodes, 4);
  EXPECT_DOUBLE_EQ(table.lessons[0].means[0], 0.5);
  EXPECT_EQ(table.lessons[1].episodes, 0);
  EXPECT_TRUE(std::isnan(table.lessons[1].means[0]));
  EXPECT_NE(lesson_table_markdown(table, 2).find("| 0 | - |"), std::string::npos);
}

TEST(LessonTable, UnknownNamesAreErrorsThatListWhatTheRunHas) {
  const auto run = self_play_run();
  auto message = [&](const std::string& parameter, const std::string& behavior,
                     const std::string& metric) {
    try {
      summarize_lessons(run, parameter, behavior, metric.empty() ? std::vector<std::string>{}
                                                                 : std::vector<std::string>{metric},
                        {});
    } catch (const std::exception& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message("speed", "", "").find("'speed' is not in metrics/episodes.csv (it has: level)"),
            std::string::npos);
  EXPECT_NE(message("level", "Runner", "").find("the run's behaviors: Hider, Seeker"),
            std::string::npos);
  EXPECT_NE(message("level", "", "tag_rate").find("it has: fort_rate, hider0_idle"),
            std::string::npos);
  EXPECT_NE(message("level", "", "Hider_step").find("'Hider_step' is not"), std::string::npos);
  EXPECT_EQ(message("level", "Hider", "fort_rate"), "no error");
}

class RltLessonsTest : public testing::Test {
 protected:
  void SetUp() override {
    root_ = fs::temp_directory_path() /
            ("rlt_lessons_test_" + std::to_string(::getpid()) + "_" +
             testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(root_);
    fs::create_directories(root_);
  }
  void TearDown() override { fs::remove_all(root_); }

  test::CommandResult rlt(const std::string& args) {
    return test::run_shell(std::string(RLT_BINARY) + " lessons " + args, root_);
  }

  // a run folder of the hide-and-seek configuration whose episodes.csv is self_play_run()'s
  fs::path make_run() {
    const fs::path dir = root_ / "run";
    fs::create_directories(dir / "metrics");
    fs::copy_file("configs/hide_and_seek.yaml", dir / "configuration.yaml");
    std::ofstream(dir / "metrics/Hider.csv") << "step,mean_return\n";
    std::ofstream(dir / "metrics/Seeker.csv") << "step,mean_return\n";
    std::ofstream episodes(dir / "metrics/episodes.csv");
    const auto run = self_play_run();
    for (size_t c = 0; c < run.episodes.columns.size(); ++c)
      episodes << (c ? "," : "") << run.episodes.columns[c];
    episodes << "\n";
    for (const auto& row : run.episodes.rows) {
      for (size_t c = 0; c < row.size(); ++c) {
        episodes << (c ? "," : "");
        if (!std::isnan(row[c])) episodes << row[c];
      }
      episodes << "\n";
    }
    return dir;
  }

  fs::path root_;
};

TEST_F(RltLessonsTest, PrintsTheTableWithTheConfigurationsLessonNames) {
  const auto dir = make_run();
  const auto r = rlt(dir.string() + " --behavior Hider --metric fort_rate");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("| lesson | name | entered at (Hider steps) | Hider steps in it | visits | "
                       "episodes | fort_rate |"),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("| 0 | level1_props_000 | 0 | 200 | 2 | 4 | 0.75 |"), std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("| 1 | level1_props_010 | 100 | 250 | 2 | 4 | 0.50 |"), std::string::npos)
      << r.out;
  const auto json = rlt(dir.string() + " --behavior Hider --metric fort_rate --json");
  ASSERT_EQ(json.exit_code, 0) << json.err;
  EXPECT_NE(json.out.find("{\"lesson\":1,\"name\":\"level1_props_010\",\"entered\":100,"
                          "\"steps\":250,\"visits\":2,\"episodes\":4,\"completed_at\":null,"
                          "\"metrics\":{\"fort_rate\":0.5}}"),
            std::string::npos)
      << json.out;
}

TEST_F(RltLessonsTest, ARunWithLessonChangesGetsThemExactly) {
  const auto dir = make_run();
  std::ofstream(dir / "metrics/lessons.csv")
      << "total_steps,elapsed_s,Hider_step,Seeker_step,parameter,from_lesson,to_lesson,change,"
         "measure\n260,2.5,160,100,level,0,1,completed,0.55\n"
         "480,4.5,330,150,level,1,0,fell_back,0.01\n520,5,370,150,level,0,1,completed,0.6\n"
         "560,5.5,410,150,level,1,2,completed,0.8\n590,5.9,440,150,level,2,1,fell_back,0\n"
         "599,6,4";  // a write cut off: left out
  auto r = rlt(dir.string() + " --behavior Hider --metric fort_rate");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("| 0 | level1_props_000 | 0 | 200 | 2 | 4 | 0.60 | 0.75 |"),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("| 2 | level1_props_020 | 410 | 30 | 1 | 0 | - | - |"), std::string::npos)
      << r.out;
  // a malformed row is an error naming the file and the line
  std::ofstream(dir / "metrics/lessons.csv")
      << "total_steps,elapsed_s,Hider_step,Seeker_step,parameter,from_lesson,to_lesson,change,"
         "measure\n260,2.5,160,100,level,0,1,passed,0.55\n";
  r = rlt(dir.string() + " --behavior Hider");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("lessons.csv:2: change 'passed' is neither completed nor fell_back"),
            std::string::npos)
      << r.err;
}

TEST_F(RltLessonsTest, BadInputIsAClearError) {
  const auto dir = make_run();
  auto r = rlt((root_ / "missing").string());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("is not a folder"), std::string::npos) << r.err;
  r = rlt(dir.string() + " --parameter speed");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("curriculum parameter 'speed' is not in metrics/episodes.csv"),
            std::string::npos)
      << r.err;
  r = rlt(dir.string() + " --decimals -1");
  EXPECT_EQ(r.exit_code, 2);
  r = rlt("");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("expected one RUN_DIR"), std::string::npos) << r.err;
  // a configuration that cannot be read leaves the lessons unnamed, with a warning naming it
  std::ofstream(dir / "configuration.yaml") << "behaviors: [\n";
  r = rlt(dir.string() + " --behavior Hider --metric fort_rate");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("warning: lessons left unnamed"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("configuration.yaml"), std::string::npos) << r.err;
  EXPECT_NE(r.out.find("| 0 | - | 0 | 200 | 2 | 4 | 0.75 |"), std::string::npos) << r.out;
  fs::remove(dir / "metrics/episodes.csv");
  r = rlt(dir.string());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("has no metrics/episodes.csv"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace rlt
