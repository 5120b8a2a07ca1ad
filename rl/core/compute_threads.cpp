#include "rl/core/compute_threads.h"

#include <dlfcn.h>

#include <algorithm>
#include <cstdint>
#include <torch/torch.h>

namespace rlt {

void set_blas_threads(int threads) {
  // OpenBLAS keeps its own pool; reach it without linking against it (the BLAS is chosen by the
  // system's alternatives)
  using SetThreads = void (*)(int);
  if (auto f = reinterpret_cast<SetThreads>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads"))) f(threads);
}

void set_compute_threads(int threads) {
  torch::set_num_threads(threads);
  set_blas_threads(threads);
}

int update_threads(int obs_size, int hidden_units, int cores) {
  return int64_t(obs_size) * hidden_units >= 65536 ? std::max(1, cores) : 1;
}

}  // namespace rlt
