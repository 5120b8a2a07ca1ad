#include "rl/core/machine_info.h"

#include <torch/version.h>

#include <fstream>
#include <thread>

#include "rl/core/blas_kernels.h"

namespace rlt {

namespace {

std::string cpu_model() {
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("model name", 0) != 0) continue;
    const auto colon = line.find(':');
    if (colon == std::string::npos) break;
    const auto begin = line.find_first_not_of(" \t", colon + 1);
    if (begin == std::string::npos) break;
    return line.substr(begin);
  }
  return "unknown";
}

void compare(std::string& out, const char* what, const std::string& a, const std::string& b) {
  if (a == b) return;
  if (!out.empty()) out += ", ";
  out += std::string(what) + " " + (a.empty() ? "none" : a) + " -> " + (b.empty() ? "none" : b);
}

}  // namespace

MachineInfo current_machine() {
  MachineInfo m;
  m.cpu = cpu_model();
  m.cores = int(std::thread::hardware_concurrency());
  m.blas_kernels = openblas_core();
  m.torch_version = TORCH_VERSION;
  m.rlt_commit = build_commit();
  return m;
}

std::string machine_difference(const MachineInfo& before, const MachineInfo& now) {
  std::string out;
  compare(out, "CPU", before.cpu, now.cpu);
  compare(out, "BLAS kernels", before.blas_kernels, now.blas_kernels);
  compare(out, "LibTorch", before.torch_version, now.torch_version);
  compare(out, "rlt", before.rlt_commit, now.rlt_commit);
  return out;
}

}  // namespace rlt
