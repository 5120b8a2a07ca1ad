#include "rl/ppo/mlp_ppo_gradient.h"

#include <algorithm>
#include <cmath>

#include "rl/core/eigen_layers.h"
#include "rl/core/matrix_product.h"
#include "rl/ppo/ppo_loss.h"

namespace rlt {

namespace {

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
    multiply(in, Transpose::kNo, matrix_of(body[l].weight), Transpose::kNo, z[l]);
    z[l].rowwise() += row_of(body[l].bias);
    activate(net_.shape().activation, z[l], y[l]);
  }
}

void MlpPpoGradient::body_backward(const std::vector<DenseLayer>& body, const RowMatrix& x,
                                   const std::vector<RowMatrix>& z,
                                   const std::vector<RowMatrix>& y, RowMatrix dy) {
  for (size_t l = body.size(); l-- > 0;) {
    RowMatrix dz = activation_backward(net_.shape().activation, z[l], y[l], dy);
    const RowMatrix& in = l == 0 ? x : y[l - 1];
    MatrixMap weight_gradient = matrix_grad(body[l].weight);
    multiply(in, Transpose::kYes, dz, Transpose::kNo, weight_gradient);
    row_grad(body[l].bias) = dz.colwise().sum();
    if (l > 0) {
      dy.resize(dz.rows(), in.cols());
      multiply(dz, Transpose::kNo, matrix_of(body[l].weight), Transpose::kYes, dy);
    }
  }
}

LossValues MlpPpoGradient::compute(const MinibatchView& mb, float epsilon, float beta,
                                   float discrete_beta, float value_loss_coef) {
  const auto& shape = net_.shape();
  const auto& spec = shape.action;
  const int64_t B = mb.rows;
  const int C = spec.continuous_size, K = spec.num_branches(), M = spec.mask_size();
  const RowMatrix x = ConstMatrixMap(mb.obs, B, shape.obs_size);
  const ConstMatrixMap old(mb.old, B, 4);  // old log-prob, advantage, old value, return

  // forward: bodies
  body_forward(net_.actor_body, x, actor_z_, actor_y_);
  const RowMatrix& actor_h = actor_y_.back();
  // without a critic (MA-POCA's actor) only the policy and entropy terms
  const bool critic = shape.with_critic;
  if (critic && !shape.shared_critic) body_forward(net_.critic_body, x, critic_z_, critic_y_);
  const RowMatrix& critic_h = shape.shared_critic || !critic ? actor_h : critic_y_.back();

  Eigen::VectorXd log_prob = Eigen::VectorXd::Zero(B), entropy = Eigen::VectorXd::Zero(B);
  // forward: continuous part
  RowMatrix zc;  // [B, C] standardized actions
  Eigen::RowVectorXf log_std, std_dev;
  if (C > 0) {
    RowMatrix mean(B, C);
    multiply(actor_h, Transpose::kNo, matrix_of(net_.mean_head.weight), Transpose::kNo, mean);
    mean.rowwise() += row_of(net_.mean_head.bias);
    log_std = row_of(net_.log_std);
    std_dev = log_std.array().exp();
    zc = (ConstMatrixMap(mb.continuous, B, C) - mean).array().rowwise() / std_dev.array();
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
    multiply(actor_h, Transpose::kNo, matrix_of(net_.logits_head.weight), Transpose::kNo, logits);
    logits.rowwise() += row_of(net_.logits_head.bias);
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
  Eigen::VectorXf value = Eigen::VectorXf::Zero(B);
  if (critic) {
    value = (critic_h * matrix_of(net_.value_head.weight)).col(0);
    value.array() += net_.value_head.bias.data_ptr<float>()[0];
  }

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

    if (!critic) continue;
    const ClippedValueTerm v = clipped_value_term(value[i], old(i, 2), old(i, 3), epsilon);
    out.value += v.loss / B;
    dv[i] = float(value_loss_coef * v.gradient / B);
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
    MatrixMap mean_weight_gradient = matrix_grad(net_.mean_head.weight);
    multiply(actor_h, Transpose::kYes, d_mean, Transpose::kNo, mean_weight_gradient);
    row_grad(net_.mean_head.bias) = d_mean.colwise().sum();
    multiply(d_mean, Transpose::kNo, matrix_of(net_.mean_head.weight), Transpose::kYes, d_actor_h,
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
    MatrixMap logits_weight_gradient = matrix_grad(net_.logits_head.weight);
    multiply(actor_h, Transpose::kYes, d_logits, Transpose::kNo, logits_weight_gradient);
    row_grad(net_.logits_head.bias) = d_logits.colwise().sum();
    multiply(d_logits, Transpose::kNo, matrix_of(net_.logits_head.weight), Transpose::kYes,
             d_actor_h, /*accumulate=*/true);
  }
  if (!critic) {
    body_backward(net_.actor_body, x, actor_z_, actor_y_, std::move(d_actor_h));
    return out;
  }
  matrix_grad(net_.value_head.weight).col(0).noalias() = critic_h.transpose() * dv;
  net_.value_head.bias.grad().data_ptr<float>()[0] = dv.sum();
  RowMatrix d_critic_h = dv * matrix_of(net_.value_head.weight).transpose();

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
