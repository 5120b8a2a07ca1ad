#include "rl/core/flat_adam.h"

#include <cmath>

namespace rlt {

FlatAdam::FlatAdam(std::vector<torch::Tensor> params, double eps, double beta1, double beta2)
    : params_(std::move(params)), eps_(eps), beta1_(beta1), beta2_(beta2) {
  int64_t total = 0;
  for (const auto& p : params_) total += p.numel();
  flat_ = torch::zeros({total});
  grad_ = torch::zeros({total});
  m_ = torch::zeros({total});
  v_ = torch::zeros({total});
  relink();
}

void FlatAdam::relink() {
  torch::NoGradGuard no_grad;
  int64_t offset = 0;
  for (auto& p : params_) {
    const int64_t n = p.numel();
    auto values = p.detach().clone().reshape({n});
    flat_.narrow(0, offset, n).copy_(values);
    // the parameter becomes a view of the flat buffer; its gradient a view of the flat gradient
    p.set_(flat_.storage(), offset, p.sizes(), c10::contiguous_strides(p.sizes()));
    p.mutable_grad() = grad_.narrow(0, offset, n).view(p.sizes());
    offset += n;
  }
}

float FlatAdam::clip_grad_norm(float max_norm) {
  const float norm = grad_.norm().item<float>();
  if (norm > max_norm) grad_.mul_(max_norm / (norm + 1e-6f));
  return norm;
}

void FlatAdam::step(double lr) {
  torch::NoGradGuard no_grad;
  ++step_;
  const double bias1 = 1.0 - std::pow(beta1_, double(step_));
  const double bias2 = 1.0 - std::pow(beta2_, double(step_));
  m_.mul_(beta1_).add_(grad_, 1.0 - beta1_);
  v_.mul_(beta2_).addcmul_(grad_, grad_, 1.0 - beta2_);
  auto denom = v_.sqrt().div_(std::sqrt(bias2)).add_(eps_);
  flat_.addcdiv_(m_, denom, -lr / bias1);
}

void FlatAdam::save(torch::serialize::OutputArchive& a) const {
  a.write("m", m_);
  a.write("v", v_);
  a.write("step", torch::tensor({step_}, torch::kInt64));
}

void FlatAdam::load(torch::serialize::InputArchive& a) {
  torch::Tensor m, v, step;
  a.read("m", m);
  a.read("v", v);
  a.read("step", step);
  if (m.numel() != m_.numel() || v.numel() != v_.numel())
    throw std::runtime_error("optimizer state has " + std::to_string(m.numel()) +
                             " parameters, the network " + std::to_string(m_.numel()));
  torch::NoGradGuard no_grad;
  m_.copy_(m);
  v_.copy_(v);
  step_ = step.item<int64_t>();
}

}  // namespace rlt
