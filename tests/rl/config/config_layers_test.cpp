// Tests of base_config: a configuration laid over the file it names. Mappings merge at every
// depth, everything else replaces; problems name the file and line they are in; a base that is
// missing, not a path, or part of a cycle is an error naming the file that names it.
#include "rl/config/config_layers.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "rl/config/config_parser.h"

namespace rlt {
namespace {

// A folder of YAML files removed at the end of the test.
class TempFolder {
 public:
  TempFolder()
      : path_(std::filesystem::temp_directory_path() /
              ("rlt_config_layers_test_" + std::to_string(::getpid()))) {
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~TempFolder() { std::filesystem::remove_all(path_); }

  // Writes `text` to NAME (a path inside the folder) and returns the file's path.
  std::string write(const std::string& name, const std::string& text) const {
    const std::filesystem::path file = path_ / name;
    std::filesystem::create_directories(file.parent_path());
    std::ofstream(file) << text;
    return file.string();
  }
  std::string path(const std::string& name) const { return (path_ / name).string(); }

 private:
  std::filesystem::path path_;
};

// A whole configuration: two behaviors, settings in both layers, a curriculum.
constexpr const char* kBase = R"(default_settings:
  hyperparameters:
    batch_size: 64
    buffer_size: 640
    beta: 0.005
behaviors:
  Runner:
    trainer_type: ppo
    hyperparameters:
      learning_rate: 0.001
    max_steps: 1000
  Chaser:
    trainer_type: ppo
environment_parameters:
  level:
    curriculum:
      - name: easy
        value: 1
        completion_criteria: {behavior: Runner, measure: reward, threshold: 0.5}
      - name: hard
        value: 2
env_settings:
  env_id: CartPole
  num_envs: 4
  params: {a: 1, b: 2}
checkpoint_settings:
  run_id: base_run
)";

ConfigError load_error(const std::string& path) {
  try {
    load_run_config(path);
  } catch (const ConfigError& error) {
    return error;
  }
  ADD_FAILURE() << "no ConfigError for " << path;
  return ConfigError("", "", 0, "");
}

// The ConfigError loading `path` throws, checked to name `file`, `key_path` and `line`.
ConfigError expect_error_at(const std::string& path, const std::string& file,
                            const std::string& key_path, int line) {
  const ConfigError error = load_error(path);
  EXPECT_EQ(error.file(), file) << error.what();
  EXPECT_EQ(error.key_path(), key_path) << error.what();
  EXPECT_EQ(error.line(), line) << error.what();
  return error;
}

TEST(ConfigLayersTest, MappingsMergeKeyByKeyAndListsReplace) {
  TempFolder folder;
  folder.write("base.yaml", kBase);
  const std::string child = folder.write("experiments/child.yaml", R"(# only what changes
base_config: ../base.yaml
behaviors:
  Runner:
    hyperparameters:
      beta: 0.001
environment_parameters:
  level:
    curriculum:
      - name: only
        value: 3
env_settings:
  params: {b: 5, c: 7}
checkpoint_settings:
  run_id: child_run
)");
  const RunConfig config = load_run_config(child);
  EXPECT_EQ(config.source_file, child);
  const BehaviorConfig& runner = config.behaviors.at("Runner");
  EXPECT_FLOAT_EQ(runner.hyperparameters.beta, 0.001f);           // the child's
  EXPECT_FLOAT_EQ(runner.hyperparameters.learning_rate, 0.001f);  // the base's, beside it
  EXPECT_EQ(runner.hyperparameters.batch_size, 64);               // the base's default_settings
  EXPECT_EQ(runner.max_steps, 1000);
  EXPECT_FLOAT_EQ(config.behaviors.at("Chaser").hyperparameters.beta, 0.005f);
  const auto& lessons = config.environment_parameters.at("level").curriculum;
  ASSERT_EQ(lessons.size(), 1u);  // the child's list replaced the base's two lessons
  EXPECT_EQ(lessons[0].name, "only");
  EXPECT_EQ(config.env_settings.env_id, "CartPole");
  EXPECT_EQ(config.env_settings.num_envs, 4);
  EXPECT_EQ(config.env_settings.params.at("a"), 1.0);
  EXPECT_EQ(config.env_settings.params.at("b"), 5.0);
  EXPECT_EQ(config.env_settings.params.at("c"), 7.0);
  EXPECT_EQ(config.checkpoint_settings.run_id, "child_run");
  // what a run folder keeps is whole: it reads back without the base
  const RunConfig again = load_run_config_from_string(run_config_to_yaml(config), "copy.yaml");
  EXPECT_EQ(run_config_to_yaml(again), run_config_to_yaml(config));
}

// A mapping over a curriculum's lessons changes the lessons it names and keeps the rest.
TEST(ConfigLayersTest, AMappingOverTheLessonsChangesTheNamedOnes) {
  TempFolder folder;
  folder.write("base.yaml", kBase);
  const std::string child = folder.write("child.yaml", R"(base_config: base.yaml
environment_parameters:
  level:
    curriculum:
      hard:
        value: 5
      easy:
        completion_criteria: {threshold: 0.9}
)");
  const RunConfig config = load_run_config(child);
  const auto& lessons = config.environment_parameters.at("level").curriculum;
  ASSERT_EQ(lessons.size(), 2u);  // the base's order, not the child's
  EXPECT_EQ(lessons[0].name, "easy");
  EXPECT_EQ(lessons[1].name, "hard");
  EXPECT_EQ(lessons[1].value.value, 5.0f);
  EXPECT_EQ(lessons[0].value.value, 1.0f);  // the base's
  ASSERT_TRUE(lessons[0].completion_criteria.has_value());
  EXPECT_FLOAT_EQ(lessons[0].completion_criteria->threshold, 0.9f);  // the child's
  EXPECT_EQ(lessons[0].completion_criteria->behavior, "Runner");  // the base's, beside it
  EXPECT_EQ(lessons[0].completion_criteria->measure, CompletionMeasure::kReward);
  // a name the base does not have: the child's file and line, and the names there are
  const std::string typo = folder.write("typo.yaml", R"(base_config: base.yaml
environment_parameters:
  level:
    curriculum:
      hardest:
        value: 5
)");
  ConfigError error = load_error(typo);
  EXPECT_EQ(error.file(), typo) << error.what();
  EXPECT_EQ(error.key_path(), "environment_parameters.level.curriculum") << error.what();
  EXPECT_EQ(error.line(), 5) << error.what();
  EXPECT_NE(error.problem().find("no entry named 'hardest'"), std::string::npos) << error.what();
  EXPECT_NE(error.problem().find("'easy', 'hard'"), std::string::npos) << error.what();
  // a change that is not a mapping
  const std::string scalar = folder.write(
      "scalar.yaml",
      "base_config: base.yaml\nenvironment_parameters:\n  level:\n    curriculum:\n      hard: 3\n");
  error = load_error(scalar);
  EXPECT_EQ(error.file(), scalar) << error.what();
  EXPECT_EQ(error.line(), 5) << error.what();
  EXPECT_NE(error.problem().find("must be a mapping"), std::string::npos) << error.what();
  // a problem in a changed lesson names the child's file and line
  const std::string bad = folder.write("bad.yaml", R"(base_config: base.yaml
environment_parameters:
  level:
    curriculum:
      easy:
        completion_criteria: {threshold: lots}
)");
  error = load_error(bad);
  EXPECT_EQ(error.file(), bad) << error.what();
  EXPECT_EQ(error.key_path(), "environment_parameters.level.curriculum[0].completion_criteria.threshold")
      << error.what();
  EXPECT_EQ(error.line(), 6) << error.what();
}

// A file over `base` that changes its curriculum: `lessons`, the mapping, indented six spaces.
std::string over_lessons(const std::string& base, const std::string& lessons) {
  return "base_config: " + base + "\nenvironment_parameters:\n  level:\n    curriculum:\n" +
         lessons;
}

TEST(ConfigLayersTest, AMappingOverTheLessonsAddsAndRemovesLessons) {
  TempFolder folder;
  folder.write("base.yaml", kBase);
  const std::string child = folder.write("child.yaml", over_lessons("base.yaml", R"(      hardest:
        insert_after: hard
        value: 3
      medium:
        insert_before: hard
        value: 1.5
        completion_criteria: {behavior: Runner, measure: reward, threshold: 0.7}
      warmup:
        insert_before: easy
        value: 0
        completion_criteria: {behavior: Chaser, measure: reward, threshold: 0.2}
      medium_too:
        insert_before: hard
        value: 1.8
        completion_criteria: {behavior: Runner, measure: reward, threshold: 0.8}
      easy:
        remove: true
      hard:
        completion_criteria: {behavior: Runner, measure: reward, threshold: 0.9}
)"));
  const RunConfig config = load_run_config(child);
  const auto& lessons = config.environment_parameters.at("level").curriculum;
  std::vector<std::string> names;
  for (const auto& lesson : lessons) names.push_back(lesson.name);
  // the base's order with easy gone; two before one entry keep the child's order
  EXPECT_EQ(names, (std::vector<std::string>{"warmup", "medium", "medium_too", "hard", "hardest"}));
  ASSERT_EQ(lessons.size(), 5u);
  EXPECT_EQ(lessons[0].value.value, 0.0f);
  EXPECT_EQ(lessons[0].completion_criteria->behavior, "Chaser");
  EXPECT_EQ(lessons[1].value.value, 1.5f);
  EXPECT_FLOAT_EQ(lessons[2].completion_criteria->threshold, 0.8f);
  EXPECT_EQ(lessons[3].value.value, 2.0f);  // the base's hard, changed by the child
  EXPECT_FLOAT_EQ(lessons[3].completion_criteria->threshold, 0.9f);
  EXPECT_EQ(lessons[4].value.value, 3.0f);
  EXPECT_FALSE(lessons[4].completion_criteria.has_value());

  // A lesson that moved keeps the file of its values: the middle file gives easy a fallback, the
  // top one inserts a lesson before easy (index 0 -> 1) and lowers easy's threshold under it.
  folder.write("middle.yaml", over_lessons("base.yaml", R"(      easy:
        completion_criteria: {fallback_threshold: 0.1}
)"));
  const std::string top = folder.write("top.yaml", over_lessons("middle.yaml", R"(      warmup:
        insert_before: easy
        value: 0
        completion_criteria: {behavior: Runner, measure: reward, threshold: 0.2}
      easy:
        completion_criteria: {threshold: 0.05}
)"));
  ConfigError error = load_error(top);
  EXPECT_EQ(error.file(), folder.path("middle.yaml")) << error.what();
  EXPECT_EQ(error.key_path(),
            "environment_parameters.level.curriculum[1].completion_criteria."
            "fallback_threshold")
      << error.what();
  EXPECT_EQ(error.line(), 6) << error.what();
  // a problem in an inserted lesson names the child's line
  const std::string bad_value =
      folder.write("bad_value.yaml", over_lessons("base.yaml", R"(      warmup:
        insert_after: easy
        value: lots
)"));
  error = load_error(bad_value);
  EXPECT_EQ(error.file(), bad_value) << error.what();
  EXPECT_EQ(error.key_path(), "environment_parameters.level.curriculum[1].value") << error.what();
  EXPECT_EQ(error.line(), 7) << error.what();
  const std::string bad_criteria =
      folder.write("bad_criteria.yaml", over_lessons("base.yaml", R"(      warmup:
        insert_before: easy
        value: 0
        completion_criteria: {behavior: Runner, measure: reward, threshold: lots}
)"));
  error = load_error(bad_criteria);
  EXPECT_EQ(error.file(), bad_criteria) << error.what();
  EXPECT_EQ(error.key_path(),
            "environment_parameters.level.curriculum[0].completion_criteria.threshold")
      << error.what();
  EXPECT_EQ(error.line(), 8) << error.what();

  // a base list with two entries of one name cannot be changed by name: the base's line
  std::string twice(kBase);
  twice.replace(twice.find("- name: hard"), 12, "- name: easy");
  const std::string twice_base = folder.write("twice_base.yaml", twice);
  error = load_error(folder.write("twice.yaml", over_lessons("twice_base.yaml", R"(      easy:
        value: 3
)")));
  EXPECT_EQ(error.file(), twice_base) << error.what();
  EXPECT_EQ(error.line(), 20) << error.what();
  EXPECT_NE(error.problem().find("a second entry named 'easy'"), std::string::npos) << error.what();

  // Bad changes, each named with the child's file and line.
  struct BadChange {
    std::string lessons;  // the curriculum mapping, indented six spaces
    int line;
    std::string problem;
  };
  const std::vector<BadChange> bad = {
      {"      warmup:\n        value: 0\n", 5, "to add one, give it insert_before or insert_after"},
      {"      warmup:\n        insert_before: hardest\n        value: 0\n", 6,
       "insert_before must name an entry of the base's list (its names: 'easy', 'hard')"},
      {"      warmup:\n        insert_after: [easy]\n        value: 0\n", 6,
       "insert_after must name an entry"},
      {"      warmup:\n        insert_before: easy\n        insert_after: hard\n        value: 0\n",
       7, "not both"},
      {"      hard:\n        insert_before: easy\n", 5, "has an entry named 'hard' already"},
      {"      hard:\n        remove: false\n", 6, "remove must be true"},
      {"      hard:\n        remove: yes please\n", 6, "remove must be true"},
      {"      hard:\n        remove: true\n        value: 4\n", 6, "takes no other keys"},
      {"      hard:\n        remove: \"true\"\n", 6, "remove must be true"},
      {"      hard:\n        remove: y\n", 6, "remove must be true"},
      {"      hard:\n        remove: true\n        remove: true\n", 7,
       "key 'remove' appears twice"},
      {"      warmup:\n        insert_before: easy\n        insert_before: hard\n", 7,
       "key 'insert_before' appears twice"},
      {"      warmup:\n        insert_before: easy\n        name: cooldown\n", 7,
       "an entry's name is its key here ('warmup')"},
      {"      hard:\n        name: hardest\n", 6, "cannot be given or changed"},
      {"      \"\":\n        insert_before: easy\n", 5, "an entry's name must not be empty"},
  };
  for (size_t i = 0; i < bad.size(); ++i) {
    const std::string file = folder.write("bad" + std::to_string(i) + ".yaml",
                                          over_lessons("base.yaml", bad[i].lessons));
    error = load_error(file);
    EXPECT_EQ(error.file(), file) << error.what();
    EXPECT_EQ(error.line(), bad[i].line) << error.what();
    EXPECT_NE(error.problem().find(bad[i].problem), std::string::npos) << error.what();
  }
}

TEST(ConfigLayersTest, BasesChainAndAnAbsolutePathWorks) {
  TempFolder folder;
  const std::string base = folder.write("base.yaml", kBase);
  folder.write("middle.yaml", "base_config: " + base + "\nenv_settings:\n  num_envs: 8\n");
  const std::string top = folder.write(
      "top.yaml", "base_config: middle.yaml\nbehaviors:\n  Chaser:\n    max_steps: 77\n");
  const RunConfig config = load_run_config(top);
  EXPECT_EQ(config.env_settings.num_envs, 8);
  EXPECT_EQ(config.behaviors.at("Chaser").max_steps, 77);
  EXPECT_EQ(config.behaviors.at("Runner").max_steps, 1000);
}

TEST(ConfigLayersTest, ANullReplacesTheBasesValue) {
  TempFolder folder;
  folder.write("base.yaml", kBase);
  // the Runner's own settings go, so it has default_settings' and ML-Agents' defaults
  const std::string child =
      folder.write("child.yaml", "base_config: base.yaml\nbehaviors:\n  Runner:\n");
  const BehaviorConfig& runner = load_run_config(child).behaviors.at("Runner");
  EXPECT_EQ(runner.max_steps, 500000);
  EXPECT_FLOAT_EQ(runner.hyperparameters.learning_rate, 3e-4f);
  EXPECT_EQ(runner.hyperparameters.batch_size, 64);
}

// `key: !remove` drops the base's key at any depth, a lesson's keys too; a removal with nothing
// of the base's to drop is an error naming the file, key and line.
TEST(ConfigLayersTest, ARemoveTagDropsTheBasesKey) {
  TempFolder folder;
  folder.write("base.yaml", kBase);
  const std::string child = folder.write("child.yaml", R"(base_config: base.yaml
behaviors:
  Runner:
    hyperparameters:
      learning_rate: !remove
    max_steps: !remove
environment_parameters:
  level:
    curriculum:
      easy:
        completion_criteria: {threshold: !remove}
env_settings:
  params: {a: !remove, c: 3}
)");
  const RunConfig config = load_run_config(child);
  const BehaviorConfig& runner = config.behaviors.at("Runner");
  EXPECT_FLOAT_EQ(runner.hyperparameters.learning_rate, 3e-4f);  // ML-Agents' default again
  EXPECT_EQ(runner.max_steps, 500000);
  EXPECT_FLOAT_EQ(runner.hyperparameters.beta, 0.005f);  // beside it, the base's
  const auto& lessons = config.environment_parameters.at("level").curriculum;
  ASSERT_EQ(lessons.size(), 2u);
  EXPECT_FLOAT_EQ(lessons[0].completion_criteria->threshold, 0.0f);  // the criteria's default
  EXPECT_EQ(lessons[0].completion_criteria->behavior, "Runner");
  EXPECT_EQ(config.env_settings.params.count("a"), 0u);
  EXPECT_EQ(config.env_settings.params.at("b"), 2.0);
  EXPECT_EQ(config.env_settings.params.at("c"), 3.0);
  // a key the base does not have
  const std::string absent = folder.write(
      "absent.yaml", "base_config: base.yaml\nenv_settings:\n  params: {d: !remove}\n");
  ConfigError error = expect_error_at(absent, absent, "env_settings.params.d", 3);
  EXPECT_NE(error.problem().find("no key 'd' here to remove"), std::string::npos) << error.what();
  // a value beside the tag
  const std::string valued = folder.write(
      "valued.yaml", "base_config: base.yaml\nenv_settings:\n  params:\n    a: !remove 4\n");
  error = expect_error_at(valued, valued, "env_settings.params.a", 4);
  EXPECT_NE(error.problem().find("takes no value"), std::string::npos) << error.what();
  // a file without a base, and a lesson the file adds: nothing of a base's to drop there
  const std::string alone = folder.write(
      "alone.yaml", std::string(kBase) + "torch_settings:\n  device: !remove\n");
  error = expect_error_at(alone, alone, "torch_settings.device", 29);
  EXPECT_NE(error.problem().find("no base's key for it to drop"), std::string::npos)
      << error.what();
  const std::string added = folder.write("added.yaml", R"(base_config: base.yaml
environment_parameters:
  level:
    curriculum:
      middle:
        insert_after: easy
        value: !remove
)");
  expect_error_at(added, added, "environment_parameters.level.curriculum[1].value", 7);
  // a removal in a base is the base's problem, named so
  const std::string middle = folder.write(
      "middle.yaml", "base_config: alone.yaml\nbehaviors:\n  Runner:\n    max_steps: 5\n");
  expect_error_at(middle, alone, "torch_settings.device", 29);
}

TEST(ConfigLayersTest, AProblemNamesTheFileAndLineItIsIn) {
  TempFolder folder;
  folder.write("base.yaml", kBase);
  // in the child: the child's file and line
  const std::string child = folder.write(
      "child.yaml",
      "base_config: base.yaml\nbehaviors:\n  Runner:\n    hyperparameters:\n      beta: lots\n");
  ConfigError error = load_error(child);
  EXPECT_EQ(error.file(), child) << error.what();
  EXPECT_EQ(error.key_path(), "behaviors.Runner.hyperparameters.beta") << error.what();
  EXPECT_EQ(error.line(), 5) << error.what();
  // an unknown key in a merged mapping: the child's file and the key's line
  const std::string typo = folder.write(
      "typo.yaml", "base_config: base.yaml\nenv_settings:\n  num_env: 2\n");
  error = load_error(typo);
  EXPECT_EQ(error.file(), typo) << error.what();
  EXPECT_EQ(error.line(), 3) << error.what();
  EXPECT_NE(error.problem().find("did you mean 'num_envs'"), std::string::npos) << error.what();
  // in the base, read alone first: the base's file and line
  const std::string broken_base = folder.write(
      "broken_base.yaml", std::string(kBase) + "torch_settings:\n  device: cuda\n");
  const std::string over_broken =
      folder.write("over_broken.yaml", "base_config: broken_base.yaml\n");
  error = load_error(over_broken);
  EXPECT_EQ(error.file(), broken_base) << error.what();
  EXPECT_EQ(error.key_path(), "torch_settings.device") << error.what();
  EXPECT_EQ(error.line(), 29) << error.what();
  // in the child's curriculum, which replaced the base's: the child's line
  const std::string lesson = folder.write(
      "lesson.yaml",
      "base_config: base.yaml\nbehaviors:\n  Runner:\n    max_steps: 5\n"
      "environment_parameters:\n  level:\n    curriculum:\n      - name: easy\n        value: 1\n"
      "        completion_criteria: {behavior: Runner, threshold: lots}\n"
      "      - name: hard\n        value: 2\n");
  error = load_error(lesson);
  EXPECT_EQ(error.file(), lesson) << error.what();
  EXPECT_EQ(error.key_path(), "environment_parameters.level.curriculum[0].completion_criteria.threshold")
      << error.what();
  EXPECT_EQ(error.line(), 10) << error.what();
}

// Problems that only the layered tree has: the parser names the file each value came from.
TEST(ConfigLayersTest, AProblemOfTheLayeredTreeNamesTheFileOfTheValue) {
  TempFolder folder;
  const std::string base = folder.write("base.yaml", kBase);
  // the child raises batch_size above the base's buffer_size: the buffer_size is the base's
  const std::string raised = folder.write(
      "raised.yaml", "base_config: base.yaml\ndefault_settings:\n  hyperparameters:\n"
                     "    batch_size: 1280\n");
  ConfigError error = load_error(raised);
  EXPECT_EQ(error.file(), base) << error.what();
  EXPECT_EQ(error.key_path(), "default_settings.hyperparameters.buffer_size") << error.what();
  EXPECT_EQ(error.line(), 4) << error.what();
  EXPECT_NE(error.problem().find("must be at least batch_size (1280)"), std::string::npos)
      << error.what();
  // three files, the failing value in the middle one (in another folder, its base named
  // relative to that folder), the change that breaks it in the top one
  folder.write("middle/middle.yaml",
               "base_config: ../base.yaml\n\nbehaviors:\n  Chaser:\n    hyperparameters:\n"
               "      buffer_size: 100\n");
  const std::string top = folder.write(
      "top/top.yaml", "base_config: ../middle/middle.yaml\nbehaviors:\n  Chaser:\n"
                      "    hyperparameters:\n      batch_size: 200\n");
  error = load_error(top);
  EXPECT_EQ(error.file(), folder.path("middle/middle.yaml")) << error.what();
  EXPECT_EQ(error.key_path(), "behaviors.Chaser.hyperparameters.buffer_size") << error.what();
  EXPECT_EQ(error.line(), 6) << error.what();
  // a key that is unknown only next to the child's sibling: the key's own file and line
  std::string with_sampler(kBase);
  with_sampler.replace(with_sampler.find("environment_parameters:\n"), 24,
                       "environment_parameters:\n  speed:\n    sampler_type: uniform\n"
                       "    sampler_parameters: {min_value: 1, max_value: 2}\n");
  folder.write("sampler_base.yaml", with_sampler);
  const std::string gaussian = folder.write(
      "gaussian.yaml", "base_config: sampler_base.yaml\nenvironment_parameters:\n  speed:\n"
                       "    sampler_type: gaussian\n    sampler_parameters: {mean: 1, st_dev: 1}\n");
  error = load_error(gaussian);
  EXPECT_EQ(error.file(), folder.path("sampler_base.yaml")) << error.what();
  EXPECT_EQ(error.line(), 17) << error.what();
  EXPECT_NE(error.problem().find("min_value"), std::string::npos) << error.what();
}

TEST(ConfigLayersTest, BadBasesAreErrorsNamingTheFileThatNamesThem) {
  TempFolder folder;
  folder.write("base.yaml", kBase);
  const std::string missing = folder.write("missing.yaml", "\n\nbase_config: nowhere.yaml\n");
  ConfigError error = load_error(missing);
  EXPECT_EQ(error.file(), missing) << error.what();
  EXPECT_EQ(error.key_path(), "base_config") << error.what();
  EXPECT_EQ(error.line(), 3) << error.what();
  EXPECT_NE(error.problem().find("cannot read the configuration " + folder.path("nowhere.yaml")),
            std::string::npos)
      << error.what();
  EXPECT_NE(error.problem().find("No such file"), std::string::npos) << error.what();

  for (const char* value : {"[base.yaml]", "{file: base.yaml}", "''", "null"}) {
    const std::string not_a_path =
        folder.write("not_a_path.yaml", std::string("base_config: ") + value + "\n");
    error = load_error(not_a_path);
    EXPECT_EQ(error.key_path(), "base_config") << value << ": " << error.what();
    EXPECT_NE(error.problem().find("expected the path of a run configuration"), std::string::npos)
        << error.what();
  }

  const std::string twice =
      folder.write("twice.yaml", "base_config: base.yaml\nbase_config: base.yaml\n");
  EXPECT_NE(load_error(twice).problem().find("'base_config' appears twice"), std::string::npos);

  const std::string self = folder.write("self.yaml", "base_config: self.yaml\n");
  error = load_error(self);
  EXPECT_EQ(error.file(), self) << error.what();
  EXPECT_NE(error.problem().find("would never end"), std::string::npos) << error.what();
  const std::string a = folder.write("a.yaml", "base_config: sub/../b.yaml\n");
  folder.write("b.yaml", "base_config: a.yaml\n");
  error = load_error(a);
  EXPECT_EQ(error.file(), folder.path("b.yaml")) << error.what();
  EXPECT_NE(error.problem().find("would never end"), std::string::npos) << error.what();

  // a base that is not a configuration on its own
  const std::string partial = folder.write("partial.yaml", "env_settings:\n  num_envs: 2\n");
  const std::string over_partial = folder.write("over_partial.yaml", "base_config: partial.yaml\n");
  error = load_error(over_partial);
  EXPECT_EQ(error.file(), partial) << error.what();
  EXPECT_NE(error.problem().find("no behaviors configured"), std::string::npos) << error.what();

  // a key given twice in a mapping that merges
  const std::string repeated = folder.write(
      "repeated.yaml", "base_config: base.yaml\nenv_settings:\n  num_envs: 2\n  num_envs: 3\n");
  error = load_error(repeated);
  EXPECT_EQ(error.file(), repeated) << error.what();
  EXPECT_EQ(error.line(), 4) << error.what();
  EXPECT_NE(error.problem().find("'num_envs' appears twice"), std::string::npos) << error.what();

  // base_config is read at the top of a file only
  const std::string nested =
      folder.write("nested.yaml", std::string(kBase) + "  base_config: base.yaml\n");
  error = load_error(nested);
  EXPECT_EQ(error.key_path(), "checkpoint_settings") << error.what();
}

TEST(ConfigLayersTest, KeyOriginsFindTheNearestListedAncestor) {
  KeyOrigins base("base.yaml");
  KeyOrigins top("top.yaml");
  top.take_subtree("a.b", base);
  EXPECT_EQ(top.file_of("a.b"), "base.yaml");
  EXPECT_EQ(top.file_of("a.b.c"), "base.yaml");
  EXPECT_EQ(top.file_of("a.b[3].d"), "base.yaml");
  EXPECT_EQ(top.file_of("a.bc"), "top.yaml");
  EXPECT_EQ(top.file_of("a"), "top.yaml");
  EXPECT_EQ(top.file_of(""), "top.yaml");
  // a subtree of a subtree: the deeper entry wins
  KeyOrigins middle("middle.yaml");
  middle.take_subtree("a.b.c", base);
  KeyOrigins upper("upper.yaml");
  upper.take_subtree("a", middle);
  EXPECT_EQ(upper.file_of("a.x"), "middle.yaml");
  EXPECT_EQ(upper.file_of("a.b.c.d"), "base.yaml");
}

TEST(ConfigLayersTest, LayOverKeepsBothInputsAndTheirLines) {
  const YAML::Node under = YAML::Load("a:\n  x: 1\n  y: 2\nb: [1, 2]\n");
  const YAML::Node over = YAML::Load("\na:\n  y: 3\nb: [4]\nc: 5\n");
  KeyOrigins origins("over.yaml");
  const YAML::Node merged = lay_over(under, KeyOrigins("under.yaml"), over, "over.yaml", &origins);
  EXPECT_EQ(merged["a"]["x"].as<int>(), 1);
  EXPECT_EQ(merged["a"]["y"].as<int>(), 3);
  EXPECT_EQ(merged["b"].size(), 1u);
  EXPECT_EQ(merged["c"].as<int>(), 5);
  EXPECT_EQ(merged["a"]["x"].Mark().line, 1);  // under's line
  EXPECT_EQ(merged["a"]["y"].Mark().line, 2);  // over's line
  EXPECT_EQ(origins.file_of("a.x"), "under.yaml");
  EXPECT_EQ(origins.file_of("a.y"), "over.yaml");
  EXPECT_EQ(under["a"]["y"].as<int>(), 2);  // the inputs are unchanged
  EXPECT_EQ(under["b"].size(), 2u);
  EXPECT_FALSE(under["c"]);
}

}  // namespace
}  // namespace rlt
