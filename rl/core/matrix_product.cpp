#include "rl/core/matrix_product.h"

#include <stdexcept>
#include <string>

#include <torch/torch.h>

namespace rlt {

namespace {

// a LibTorch view of a row-major block (no copy)
torch::Tensor tensor_view(const float* data, int64_t rows, int64_t cols, int64_t row_stride) {
  return torch::from_blob(const_cast<float*>(data), {rows, cols}, {row_stride, 1}, torch::kFloat);
}

template <typename X, typename Y>
void eigen_product(const X& x, const Y& y, Eigen::Ref<RowMatrix>& out, bool accumulate) {
  if (accumulate)
    out.noalias() += x * y;
  else
    out.noalias() = x * y;
}

}  // namespace

void multiply(Eigen::Ref<const RowMatrix> a, Transpose ta, Eigen::Ref<const RowMatrix> b,
              Transpose tb, Eigen::Ref<RowMatrix> out, bool accumulate, bool force_blas) {
  const bool a_t = ta == Transpose::kYes, b_t = tb == Transpose::kYes;
  const int64_t m = a_t ? a.cols() : a.rows(), k = a_t ? a.rows() : a.cols();
  const int64_t k_b = b_t ? b.cols() : b.rows(), n = b_t ? b.rows() : b.cols();
  if (k != k_b || out.rows() != m || out.cols() != n)
    throw std::invalid_argument("multiply: a product of [" + std::to_string(m) + ", " +
                                std::to_string(k) + "] by [" + std::to_string(k_b) + ", " +
                                std::to_string(n) + "] into [" + std::to_string(out.rows()) +
                                ", " + std::to_string(out.cols()) + "]");
  if (!force_blas && m * n * k < kBlasProductMinMultiplies) {
    if (!a_t && !b_t) eigen_product(a, b, out, accumulate);
    if (!a_t && b_t) eigen_product(a, b.transpose(), out, accumulate);
    if (a_t && !b_t) eigen_product(a.transpose(), b, out, accumulate);
    if (a_t && b_t) eigen_product(a.transpose(), b.transpose(), out, accumulate);
    return;
  }
  torch::NoGradGuard no_grad;
  torch::Tensor x = tensor_view(a.data(), a.rows(), a.cols(), a.outerStride());
  torch::Tensor y = tensor_view(b.data(), b.rows(), b.cols(), b.outerStride());
  torch::Tensor z = tensor_view(out.data(), m, n, out.outerStride());
  if (a_t) x = x.t();
  if (b_t) y = y.t();
  if (accumulate)
    z.addmm_(x, y);
  else
    torch::mm_out(z, x, y);
}

}  // namespace rlt
