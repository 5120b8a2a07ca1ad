#include "rl/core/blas_kernels.h"

#include <dlfcn.h>
#include <unistd.h>

#include <cstdlib>

namespace rlt {

std::string openblas_core() {
  // reached without linking against OpenBLAS: the system's alternatives choose the BLAS
  using CoreName = char* (*)();
  auto f = reinterpret_cast<CoreName>(dlsym(RTLD_DEFAULT, "openblas_get_corename"));
  const char* name = f != nullptr ? f() : nullptr;
  return name != nullptr ? std::string(name) : std::string();
}

std::string better_openblas_core(const std::string& core, bool has_avx512, bool has_avx2) {
  if (core != "Prescott") return "";
  if (has_avx512) return "SkylakeX";
  if (has_avx2) return "Haswell";
  return "";
}

void use_best_openblas_kernels(char** argv) {
  if (std::getenv("OPENBLAS_CORETYPE") != nullptr) return;
#if defined(__x86_64__) || defined(__i386__)
  const bool avx512 = __builtin_cpu_supports("avx512f");
  const bool avx2 = __builtin_cpu_supports("avx2");
#else
  const bool avx512 = false, avx2 = false;
#endif
  const std::string core = better_openblas_core(openblas_core(), avx512, avx2);
  if (core.empty()) return;
  setenv("OPENBLAS_CORETYPE", core.c_str(), 1);
  execv("/proc/self/exe", argv);
  unsetenv("OPENBLAS_CORETYPE");  // the new start failed: go on with what OpenBLAS chose
}

}  // namespace rlt
