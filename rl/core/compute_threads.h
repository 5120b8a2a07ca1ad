// Threads of the learner's linear algebra.
//
// The networks of small tasks are too small for multi-threaded matrix products: measured on 2 cores
// with CartPole's 64-64 MLP, LibTorch and OpenBLAS each running 2 threads cut end-to-end throughput
// from 51k to 20k env steps/s (the two pools oversubscribe the cores and spin). The learner
// therefore runs on one thread by default while environments use the rest.
#pragma once

namespace rlt {

// Sets LibTorch's intra-op threads and, when the BLAS in use is OpenBLAS, its thread count.
void set_compute_threads(int threads);

}  // namespace rlt
