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
// Sets only the BLAS's threads (matrix products), leaving LibTorch's OpenMP pool alone: its
// threads spin between element-wise operations and, measured on hide-and-seek's updates, cost
// more than they gave.
void set_blas_threads(int threads);

// Threads for a learner update (environments are idle then): every core once the first layer's
// matrix product is large (obs_size x hidden_units >= 65536: hide-and-seek's 919 x 256 is 3.6x
// that), one thread below, where the thread pools' overhead outweighs the work.
int update_threads(int obs_size, int hidden_units, int cores);

}  // namespace rlt
