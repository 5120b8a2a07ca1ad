// The shipped CartPole configuration trained for its 500k steps with `rlt train`, then evaluated
// with `rlt eval --episodes 20 --json`, reaches a mean return of at least 475. Label: learning.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdio>
#include <filesystem>
#include <regex>
#include <string>

namespace fs = std::filesystem;

namespace {

std::string run(const std::string& command, int* exit_code) {
  std::string out;
  FILE* pipe = popen(command.c_str(), "r");
  char buf[4096];
  while (size_t n = fread(buf, 1, sizeof buf, pipe)) out.append(buf, n);
  const int status = pclose(pipe);
  *exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return out;
}

TEST(CartPoleCli, TrainFor500kThenEvalReaches475) {
  const fs::path root = fs::temp_directory_path() / ("rlt_cartpole_cli_" + std::to_string(::getpid()));
  fs::remove_all(root);
  int code = 0;
  const std::string rlt = RLT_BINARY;
  run(rlt + " train " RLT_SOURCE_DIR "/configs/cartpole_ppo.yaml --results-dir " + root.string() +
          " --run-id cartpole 2>&1",
      &code);
  ASSERT_EQ(code, 0);
  const std::string out =
      run(rlt + " eval " + (root / "cartpole").string() + " --episodes 20 --json", &code);
  ASSERT_EQ(code, 0) << out;
  std::smatch m;
  ASSERT_TRUE(std::regex_search(out, m, std::regex(R"("mean_return":([-0-9.e+]+))"))) << out;
  std::printf("rlt eval after 500k steps: %s", out.c_str());
  EXPECT_GE(std::stod(m[1]), 475.0) << out;
  EXPECT_NE(out.find("\"episodes\":20"), std::string::npos) << out;
  fs::remove_all(root);
}

}  // namespace
