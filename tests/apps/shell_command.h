// Runs a command line through the shell for the tests that run `rlt` as a process, with its
// stdout and stderr captured in files of a scratch folder.
#pragma once

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace rlt::test {

struct CommandResult {
  int exit_code = -1;  // -1 when the command did not exit normally
  std::string out, err;
};

// the whole of a text file ("" when it cannot be read)
inline std::string read_text(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// `command` (quoted as the shell needs) with stdout and stderr in `scratch`/stdout.txt and
// stderr.txt, overwritten by the next command
inline CommandResult run_shell(const std::string& command, const std::filesystem::path& scratch) {
  const auto out = scratch / "stdout.txt", err = scratch / "stderr.txt";
  const int status =
      std::system((command + " > '" + out.string() + "' 2> '" + err.string() + "'").c_str());
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, read_text(out), read_text(err)};
}

}  // namespace rlt::test
