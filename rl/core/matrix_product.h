// Dense products of row-major float matrices for the hand-written learner (MlpPpoGradient).
//
// Small products stay in Eigen: a call through LibTorch costs a few microseconds, more than a
// CartPole-sized product takes. Large ones go through LibTorch's BLAS, which runs its kernels on as
// many threads as set_blas_threads() allows during an update. Eigen here has no OpenMP, so its
// products use one core: measured on a Zen 3 with hide-and-seek's 943 x 256 bodies, they were 14%
// of a training run's cycles while the second core waited.
#pragma once

#include <cstdint>

#include <Eigen/Core>

namespace rlt {

// [rows, cols], row-major: the layout of LibTorch tensors and of the networks' activations
using RowMatrix = Eigen::Matrix<float, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

// products with at least this many multiply-adds (rows x inner x cols) go through the BLAS
constexpr int64_t kBlasProductMinMultiplies = int64_t(1) << 22;

enum class Transpose { kNo, kYes };

// out = op(a) * op(b) (out += ... when accumulate), op transposing where asked; out must already
// have the product's shape and must not overlap a or b. Throws std::invalid_argument on a shape
// mismatch. force_blas takes the BLAS path whatever the size (for tests).
void multiply(Eigen::Ref<const RowMatrix> a, Transpose ta, Eigen::Ref<const RowMatrix> b,
              Transpose tb, Eigen::Ref<RowMatrix> out, bool accumulate = false,
              bool force_blas = false);

}  // namespace rlt
