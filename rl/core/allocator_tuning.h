// glibc malloc settings for training.
//
// LibTorch allocates every intermediate tensor with malloc. Minibatch tensors of a few hundred KB
// are above glibc's default mmap threshold (128 KB, adjusted dynamically), so each is mapped and
// unmapped again: system calls and page faults on every operation. Measured with
// `rlt bench train configs/pendulum_ppo.yaml` (512-sample minibatches): about 2 s of the run's 7 s
// were system time. Raising the mmap and trim thresholds keeps freed memory in the heap for reuse.
#pragma once

namespace rlt {

// Process-wide: sets M_MMAP_THRESHOLD and M_TRIM_THRESHOLD to 256 MB and M_TOP_PAD to 64 MB.
void tune_allocator_for_training();

}  // namespace rlt
