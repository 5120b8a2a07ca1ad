#include "rl/ppo/mlp_ppo_gradient.h"

#include <algorithm>
#include <cmath>

#include "rl/core/matrix_product.h"

namespace rlt {

namespace {

using ConstMap = Eigen::Map<const RowMatrix>;
using Map = Eigen::Map<RowMatrix>;
using ConstRowMap = Eigen::Map<const Eigen::RowVectorXf>;
using RowMap = Eigen::Map<Eigen::RowVectorXf>;

ConstMap weight_of(const torch::Tensor& w) { return ConstMap(w.data_ptr<float>(), w.size(0), w.size(1)); }
ConstRowMap bias_of(const torch::Tensor& b) { return ConstRowMap(b.data_ptr<float>(), b.size(0)); }
Map weight_grad(const torch::Tensor& w) {
  return Map(w.grad().data_ptr<float>(), w.size(0), w.size(1));
}
RowMap bias_grad(const torch::Tensor& b) { return RowMap(b.grad().data_ptr<float>(), b.size(0)); }

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

// dy * f'(z) with y = f(z)
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

// gradient share of the first argument of min/max(a, b): 1 when it alone is chosen, 1/2 on a tie
inline double share(bool chosen, bool tie) { return tie ? 0.5 : (chosen ? 1.0 : 0.0); }

}  // namespace

void MlpPpoGradient::body_forward(const std::vector<DenseLayer>& body, const RowMatrix& x,
                                  std::vector<RowMatrix>& z, std::vector<RowMatrix>& y) const {
  z.resize(body.size());
  y.resize(body.size());
  for (size_t l = 0; l < body.size(); ++l) {
    const RowMatrix& in = l == 0 ? x : y[l - 1];
    z[l].resize(in.rows(), body[l].weight.size(1));
    multiply(in, Transpose::kNo, weight_of(body[l].weight), Transpose::kNo, z[l]);
    z[l].rowwise() += bias_of(body[l].bias);
    activate(net_.shape().activation, z[l], y[l]);
  }
}

void MlpPpoGradient::body_backward(const std::vector<DenseLayer>& body, const RowMatrix& x,
                                   const std::vector<RowMatrix>& z,
                                   const std::vector<RowMatrix>& y, RowMatrix dy) {
  for (size_t l = body.size(); l-- > 0;) {
    RowMatrix dz = activation_backward(net_.shape().activation, z[l], y[l], dy);
    const RowMatrix& in = l == 0 ? x : y[l - 1];
    Map weight_gradient = weight_grad(body[l].weight);
    multiply(in, Transpose::kYes, dz, Transpose::kNo, weight_gradient);
    bias_grad(body[l].bias) = dz.colwise().sum();
    if (l > 0) {
      dy.resize(dz.rows(), in.cols());
      multiply(dz, Transpose::kNo, weight_of(body[l].weight), Transpose::kYes, dy);
    }
  }
}

LossValues MlpPpoGradient::compute(const MinibatchView& mb, float epsilon, float beta,
                                   float discrete_beta, float value_loss_coef) {
  const auto& shape = net_.shape();
  const auto& spec = shape.action;
  const int64_t B = mb.rows;
  const int C = spec.continuous_size, K = spec.num_branches(), M = spec.mask_size();
  const RowMatrix x = ConstMap(mb.obs, B, shape.obs_size);
  const ConstMap old(mb.old, B, 4);  // old log-prob, advantage, old value, return

  // forward: bodies
  body_forward(net_.actor_body, x, actor_z_, actor_y_);
  const RowMatrix& actor_h = actor_y_.back();
  if (!shape.shared_critic) body_forward(net_.critic_body, x, critic_z_, critic_y_);
  const RowMatrix& critic_h = shape.shared_critic ? actor_h : critic_y_.back();

  Eigen::VectorXd log_prob = Eigen::VectorXd::Zero(B), entropy = Eigen::VectorXd::Zero(B);
  // forward: continuous part
  RowMatrix zc;  // [B, C] standardized actions
  Eigen::RowVectorXf log_std, std_dev;
  if (C > 0) {
    RowMatrix mean(B, C);
    multiply(actor_h, Transpose::kNo, weight_of(net_.mean_head.weight), Transpose::kNo, mean);
    mean.rowwise() += bias_of(net_.mean_head.bias);
    log_std = bias_of(net_.log_std);
    std_dev = log_std.array().exp();
    zc = (ConstMap(mb.continuous, B, C) - mean).array().rowwise() / std_dev.array();
    const double half_log_2pi = 0.5 * std::log(2.0 * M_PI);
    const double row_entropy = C * (0.5 + half_log_2pi) + log_std.cast<double>().sum();
    for (int64_t i = 0; i < B; ++i) {
      for (int j = 0; j < C; ++j)
        log_prob[i] += -0.5 * double(zc(i, j)) * zc(i, j) - log_std[j] - half_log_2pi;
      entropy[i] += row_entropy;
    }
  }
  // forward: discrete branches (masked softmax)
  RowMatrix probs, log_probs;  // [B, M]
  RowMatrix branch_entropy;    // [B, K]
  if (K > 0) {
    RowMatrix logits(B, M);
    multiply(actor_h, Transpose::kNo, weight_of(net_.logits_head.weight), Transpose::kNo, logits);
    logits.rowwise() += bias_of(net_.logits_head.bias);
    probs.setZero(B, M);
    log_probs.setZero(B, M);
    branch_entropy.setZero(B, K);
    for (int64_t i = 0; i < B; ++i) {
      int offset = 0;
      for (int k = 0; k < K; ++k) {
        const int n = spec.discrete_branches[k];
        auto allowed = [&](int o) { return !mb.mask || mb.mask[i * M + offset + o] > 0.5f; };
        float top = -INFINITY;
        for (int o = 0; o < n; ++o)
          if (allowed(o)) top = std::max(top, logits(i, offset + o));
        double total = 0;
        for (int o = 0; o < n; ++o)
          if (allowed(o)) total += std::exp(double(logits(i, offset + o) - top));
        const double log_total = std::log(total);
        double h = 0;
        for (int o = 0; o < n; ++o) {
          if (!allowed(o)) continue;
          const double lp = double(logits(i, offset + o) - top) - log_total;
          log_probs(i, offset + o) = float(lp);
          probs(i, offset + o) = float(std::exp(lp));
          h -= std::exp(lp) * lp;
        }
        branch_entropy(i, k) = float(h);
        entropy[i] += h;
        log_prob[i] += log_probs(i, offset + mb.discrete[i * K + k]);
        offset += n;
      }
    }
  }
  // forward: value
  Eigen::VectorXf value = (critic_h * weight_of(net_.value_head.weight)).col(0);
  value.array() += net_.value_head.bias.data_ptr<float>()[0];

  // loss and its gradient with respect to log-probabilities and values
  LossValues out;
  Eigen::VectorXf g(B), dv(B);  // d total / d log_prob, d total / d value
  for (int64_t i = 0; i < B; ++i) {
    const double adv = old(i, 1);
    const double log_ratio = float(log_prob[i]) - old(i, 0);
    const double ratio = std::exp(log_ratio);
    const double clipped = std::clamp(ratio, 1.0 - epsilon, 1.0 + epsilon);
    const double s1 = ratio * adv, s2 = clipped * adv;
    out.policy -= std::min(s1, s2) / B;
    out.approx_kl += (ratio - 1.0 - log_ratio) / B;
    const bool in_range = ratio >= 1.0 - epsilon && ratio <= 1.0 + epsilon;
    if (std::abs(ratio - 1.0) > epsilon) out.clip_fraction += 1.0 / B;
    const double d_min = share(s1 < s2, s1 == s2) * ratio * adv +
                         share(s2 < s1, s1 == s2) * (in_range ? ratio * adv : 0.0);
    g[i] = float(-d_min / B);

    const double ret = old(i, 3), old_v = old(i, 2), v = value[i];
    const double delta = std::clamp(v - old_v, -double(epsilon), double(epsilon));
    const double v_clipped = old_v + delta;
    const double l1 = (ret - v) * (ret - v), l2 = (ret - v_clipped) * (ret - v_clipped);
    out.value += std::max(l1, l2) / B;
    const bool delta_in_range = v - old_v >= -epsilon && v - old_v <= epsilon;
    const double d_max = share(l1 > l2, l1 == l2) * -2 * (ret - v) +
                         share(l2 > l1, l1 == l2) * (delta_in_range ? -2 * (ret - v_clipped) : 0.0);
    dv[i] = float(value_loss_coef * d_max / B);
  }
  out.entropy = entropy.mean();
  out.total = out.policy + value_loss_coef * out.value - beta * out.entropy;
  // the branches' bonus at discrete_beta instead of beta (nothing changes when the two are equal)
  if (discrete_beta != beta && K > 0)
    out.total -= (discrete_beta - beta) * branch_entropy.cast<double>().sum() / double(B);

  // backward: heads
  RowMatrix d_actor_h = RowMatrix::Zero(B, actor_h.cols());
  if (C > 0) {
    RowMatrix d_mean = zc.array().rowwise() / std_dev.array();
    d_mean.array().colwise() *= g.array();
    Map mean_weight_gradient = weight_grad(net_.mean_head.weight);
    multiply(actor_h, Transpose::kYes, d_mean, Transpose::kNo, mean_weight_gradient);
    bias_grad(net_.mean_head.bias) = d_mean.colwise().sum();
    multiply(d_mean, Transpose::kNo, weight_of(net_.mean_head.weight), Transpose::kYes, d_actor_h,
             /*accumulate=*/true);
    RowMatrix z2_minus_1 = zc.array().square() - 1.f;
    RowMap log_std_grad(net_.log_std.grad().data_ptr<float>(), C);
    log_std_grad = (z2_minus_1.array().colwise() * g.array()).colwise().sum() - beta;
  }
  if (K > 0) {
    RowMatrix d_logits(B, M);
    for (int64_t i = 0; i < B; ++i) {
      int offset = 0;
      for (int k = 0; k < K; ++k) {
        const int n = spec.discrete_branches[k];
        const int chosen = int(mb.discrete[i * K + k]);
        for (int o = 0; o < n; ++o) {
          const float p = probs(i, offset + o);
          d_logits(i, offset + o) = g[i] * ((o == chosen ? 1.f : 0.f) - p) +
                                    discrete_beta / B * p *
                                        (log_probs(i, offset + o) + branch_entropy(i, k));
        }
        offset += n;
      }
    }
    Map logits_weight_gradient = weight_grad(net_.logits_head.weight);
    multiply(actor_h, Transpose::kYes, d_logits, Transpose::kNo, logits_weight_gradient);
    bias_grad(net_.logits_head.bias) = d_logits.colwise().sum();
    multiply(d_logits, Transpose::kNo, weight_of(net_.logits_head.weight), Transpose::kYes,
             d_actor_h, /*accumulate=*/true);
  }
  weight_grad(net_.value_head.weight).col(0).noalias() = critic_h.transpose() * dv;
  net_.value_head.bias.grad().data_ptr<float>()[0] = dv.sum();
  RowMatrix d_critic_h = dv * weight_of(net_.value_head.weight).transpose();

  // backward: bodies
  if (shape.shared_critic) {
    body_backward(net_.actor_body, x, actor_z_, actor_y_, d_actor_h + d_critic_h);
  } else {
    body_backward(net_.actor_body, x, actor_z_, actor_y_, std::move(d_actor_h));
    body_backward(net_.critic_body, x, critic_z_, critic_y_, std::move(d_critic_h));
  }
  return out;
}

}  // namespace rlt
