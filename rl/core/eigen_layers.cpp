#include "rl/core/eigen_layers.h"

namespace rlt {

void activate(Activation a, const RowMatrix& z, RowMatrix& y) {
  switch (a) {
    case Activation::kTanh:
      y = z.array().tanh();
      return;
    case Activation::kRelu:
      y = z.cwiseMax(0.f);
      return;
    case Activation::kSwish:
      y = z.array() / (1.f + (-z.array()).exp());
      return;
  }
}

RowMatrix activation_backward(Activation a, const RowMatrix& z, const RowMatrix& y,
                              const RowMatrix& dy) {
  switch (a) {
    case Activation::kTanh:
      return dy.array() * (1.f - y.array().square());
    case Activation::kRelu:
      return dy.array() * (z.array() > 0.f).cast<float>();
    case Activation::kSwish:
      break;
  }
  RowMatrix s = (1.f + (-z.array()).exp()).inverse();
  return dy.array() * s.array() * (1.f + z.array() * (1.f - s.array()));
}

}  // namespace rlt
