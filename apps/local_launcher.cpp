#include "apps/local_launcher.h"

#include <netinet/in.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <iostream>
#include <stdexcept>
#include <thread>

namespace rlt {

namespace {

// a TCP port nobody listens on now
int free_port() {
  const int s = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  socklen_t length = sizeof address;
  if (s < 0 || ::bind(s, reinterpret_cast<sockaddr*>(&address), sizeof address) != 0 ||
      ::getsockname(s, reinterpret_cast<sockaddr*>(&address), &length) != 0)
    throw std::runtime_error("cannot find a free port for the ranks");
  ::close(s);
  return ntohs(address.sin_port);
}

}  // namespace

std::vector<std::string> rank_command(const std::string& command,
                                      const std::vector<std::string>& args, int nproc) {
  std::vector<std::string> out{command};
  bool threads = false;
  for (size_t i = 0; i < args.size(); ++i) {
    if (args[i] == "--nproc") {
      ++i;
      continue;
    }
    threads |= args[i] == "--threads";
    out.push_back(args[i]);
  }
  if (!threads) {
    const int cores = int(std::max(1u, std::thread::hardware_concurrency()));
    out.push_back("--threads");
    out.push_back(std::to_string(std::max(1, cores / nproc)));
  }
  return out;
}

int launch_local_ranks(int nproc, const std::vector<std::string>& args, double grace_seconds) {
  const std::string port = std::to_string(free_port());
  std::vector<pid_t> ranks;
  for (int r = 0; r < nproc; ++r) {
    const pid_t pid = ::fork();
    if (pid < 0) throw std::runtime_error("cannot start rank " + std::to_string(r));
    if (pid == 0) {
      ::setenv("MASTER_ADDR", "127.0.0.1", 1);
      ::setenv("MASTER_PORT", port.c_str(), 1);
      ::setenv("WORLD_SIZE", std::to_string(nproc).c_str(), 1);
      ::setenv("RANK", std::to_string(r).c_str(), 1);
      ::setenv("LOCAL_RANK", std::to_string(r).c_str(), 1);
      std::vector<char*> argv{const_cast<char*>("rlt")};
      for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
      argv.push_back(nullptr);
      ::execv("/proc/self/exe", argv.data());
      std::perror("rlt: cannot start a rank");
      ::_exit(127);
    }
    ranks.push_back(pid);
  }
  int status_of_first_failure = 0;
  size_t running = ranks.size();
  auto failed_at = std::chrono::steady_clock::time_point::max();
  while (running > 0) {
    int status = 0;
    const pid_t pid = ::waitpid(-1, &status, WNOHANG);
    if (pid > 0) {
      --running;
      const int code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
      if (code != 0 && status_of_first_failure == 0) {
        status_of_first_failure = code;
        failed_at = std::chrono::steady_clock::now();
        for (size_t r = 0; r < ranks.size(); ++r)
          if (ranks[r] == pid)
            std::cerr << "rlt: rank " << r << " failed (exit status " << code << ")\n";
      }
      continue;
    }
    if (std::chrono::steady_clock::now() - failed_at >
        std::chrono::duration<double>(grace_seconds)) {
      for (pid_t p : ranks) ::kill(p, SIGKILL);
      failed_at = std::chrono::steady_clock::time_point::max();
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return status_of_first_failure;
}

}  // namespace rlt
