// Which kernels OpenBLAS runs the learner's matrix products with.
//
// Debian's OpenBLAS (0.3.21 in bookworm) is built for every x86 kernel family and picks one by the
// CPU's model number when it loads. A CPU newer than that list gets its oldest family, "Prescott"
// (SSE3): measured on an Intel Xeon with AVX-512, a 2048^3 single-precision product ran at 64
// GFLOP/s on 2 threads, 164 with OPENBLAS_CORETYPE=Haswell and 311 with SkylakeX, and hide-and-seek
// training went from 1.8k to 3.6k agent steps/s. OpenBLAS reads OPENBLAS_CORETYPE once, when it
// loads, so the only way to change the family is to start the program again with it set.
#pragma once

#include <string>

namespace rlt {

// the kernel family OpenBLAS runs with ("Haswell", "Prescott", ...), or "" when the BLAS is not
// OpenBLAS
std::string openblas_core();

// the OPENBLAS_CORETYPE to ask for, or "" to keep what OpenBLAS chose: only when it fell back to
// Prescott on a CPU with AVX-512 (SkylakeX) or AVX2 (Haswell)
std::string better_openblas_core(const std::string& core, bool has_avx512, bool has_avx2);

// When OPENBLAS_CORETYPE is not set and better_openblas_core() names a family for this CPU: sets
// it and executes this program again with the same arguments (call it first thing in main).
// Returns when there is nothing to do or the new start failed; a user's own OPENBLAS_CORETYPE is
// always kept.
void use_best_openblas_kernels(char** argv);

}  // namespace rlt
