// Eigen views of LibTorch parameters and the activations' forward and backward passes: the shared
// pieces of the hand-written gradients (MlpPpoGradient, PocaCriticGradient) and, for the
// activations, of the Eigen actor (FastActor).
//
// A parameter's view aliases the tensor's storage, and a gradient view aliases its .grad(), which
// FlatAdam keeps as views into one flat buffer: writing through it is how the hand-written
// gradients hand their results to the optimizer.
#pragma once

#include <torch/torch.h>

#include "rl/core/matrix_product.h"
#include "rl/core/policy_network.h"

namespace rlt {

using ConstMatrixMap = Eigen::Map<const RowMatrix>;
using MatrixMap = Eigen::Map<RowMatrix>;
using ConstRowMap = Eigen::Map<const Eigen::RowVectorXf>;
using RowMap = Eigen::Map<Eigen::RowVectorXf>;

// a 2-D parameter as a matrix of its own shape (DenseLayer: [in, out]; torch::nn::Linear:
// [out, in]), and its gradient
inline ConstMatrixMap matrix_of(const torch::Tensor& w) {
  return ConstMatrixMap(w.data_ptr<float>(), w.size(0), w.size(1));
}
inline MatrixMap matrix_grad(const torch::Tensor& w) {
  return MatrixMap(w.grad().data_ptr<float>(), w.size(0), w.size(1));
}
// a 1-D parameter (a bias) as a row, and its gradient
inline ConstRowMap row_of(const torch::Tensor& b) {
  return ConstRowMap(b.data_ptr<float>(), b.size(0));
}
inline RowMap row_grad(const torch::Tensor& b) {
  return RowMap(b.grad().data_ptr<float>(), b.size(0));
}

// y = f(z), elementwise
void activate(Activation a, const RowMatrix& z, RowMatrix& y);

// dy * f'(z), given y = f(z) (tanh' = 1 - y^2, relu' = 1[z > 0], swish' = s(z) (1 + z (1 - s(z))))
RowMatrix activation_backward(Activation a, const RowMatrix& z, const RowMatrix& y,
                              const RowMatrix& dy);

}  // namespace rlt
