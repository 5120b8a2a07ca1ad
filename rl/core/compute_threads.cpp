#include "rl/core/compute_threads.h"

#include <dlfcn.h>
#include <torch/torch.h>

namespace rlt {

void set_compute_threads(int threads) {
  torch::set_num_threads(threads);
  // OpenBLAS keeps its own pool; reach it without linking against it (the BLAS is chosen by the
  // system's alternatives)
  using SetThreads = void (*)(int);
  if (auto f = reinterpret_cast<SetThreads>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads"))) f(threads);
}

}  // namespace rlt
