// BLAS kernels: the fallback is recognised, and OpenBLAS (the BLAS setup.sh installs) names its own.
#include "rl/core/blas_kernels.h"

#include <gtest/gtest.h>

namespace rlt {
namespace {

TEST(BlasKernelsTest, OnlyThePrescottFallbackIsReplaced) {
  EXPECT_EQ(better_openblas_core("Prescott", true, true), "SkylakeX");
  EXPECT_EQ(better_openblas_core("Prescott", false, true), "Haswell");
  EXPECT_EQ(better_openblas_core("Prescott", false, false), "");  // an old CPU: Prescott is right
  EXPECT_EQ(better_openblas_core("Haswell", true, true), "");     // OpenBLAS knew the CPU
  EXPECT_EQ(better_openblas_core("", true, true), "");            // not OpenBLAS
}

TEST(BlasKernelsTest, OpenBlasNamesItsKernels) {
  const std::string core = openblas_core();
  EXPECT_FALSE(core.empty()) << "the BLAS in use is not OpenBLAS (libopenblas0-pthread)";
}

}  // namespace
}  // namespace rlt
