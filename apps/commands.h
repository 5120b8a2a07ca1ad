// The `rlt` subcommands. Each returns the process exit code.
#pragma once

#include <string>
#include <vector>

namespace rlt {

int run_train(const std::vector<std::string>& args);
int run_eval(const std::vector<std::string>& args);
int run_export(const std::vector<std::string>& args);
int run_envs(const std::vector<std::string>& args);
int run_bench(const std::vector<std::string>& args);
int run_plot(const std::vector<std::string>& args);
int run_replay(const std::vector<std::string>& args);
int run_lessons(const std::vector<std::string>& args);

extern const char* const kTrainHelp;
extern const char* const kEvalHelp;
extern const char* const kExportHelp;
extern const char* const kEnvsHelp;
extern const char* const kBenchHelp;
extern const char* const kPlotHelp;
extern const char* const kReplayHelp;
extern const char* const kLessonsHelp;

}  // namespace rlt
