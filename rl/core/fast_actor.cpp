#include "rl/core/fast_actor.h"

#include <cmath>

#include "rl/core/eigen_layers.h"
#include "rl/core/policy_network.h"

namespace rlt {

double standard_normal(std::mt19937_64& rng) {
  const double u1 = 1.0 - uniform01(rng);  // (0, 1]
  const double u2 = uniform01(rng);
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2);
}

namespace {
RowMatrix to_matrix(const torch::Tensor& t) {
  auto c = t.detach().contiguous();
  RowMatrix m(c.size(0), c.size(1));
  std::memcpy(m.data(), c.data_ptr<float>(), sizeof(float) * c.numel());
  return m;
}
Eigen::RowVectorXf to_row(const torch::Tensor& t) {
  auto c = t.detach().contiguous();
  Eigen::RowVectorXf v(c.numel());
  std::memcpy(v.data(), c.data_ptr<float>(), sizeof(float) * c.numel());
  return v;
}
}  // namespace

void FastActor::copy_from(const PolicyNetworkImpl& net, const RunningNormalizer* normalizer) {
  const auto& shape = net.shape();
  action_ = shape.action;
  activation_ = shape.activation;
  shared_critic_ = shape.shared_critic;
  auto copy_layer = [](const DenseLayer& d) { return Layer{to_matrix(d.weight), to_row(d.bias)}; };
  actor_body_.clear();
  critic_body_.clear();
  for (const auto& l : net.actor_body) actor_body_.push_back(copy_layer(l));
  for (const auto& l : net.critic_body) critic_body_.push_back(copy_layer(l));
  if (action_.continuous_size > 0) {
    mean_head_ = copy_layer(net.mean_head);
    log_std_ = to_row(net.log_std);
  }
  if (action_.num_branches() > 0) logits_head_ = copy_layer(net.logits_head);
  with_critic_ = shape.with_critic;
  if (with_critic_) value_head_ = copy_layer(net.value_head);
  normalize_ = normalizer != nullptr;
  if (normalize_) {
    auto mean = normalizer->mean_float();
    auto inv = normalizer->inverse_std();
    obs_mean_ = Eigen::Map<Eigen::RowVectorXf>(mean.data(), mean.size());
    obs_inv_std_ = Eigen::Map<Eigen::RowVectorXf>(inv.data(), inv.size());
  }
}

RowMatrix FastActor::normalized(const RowMatrix& obs) const {
  if (!normalize_) return obs;
  RowMatrix x = (obs.rowwise() - obs_mean_).array().rowwise() * obs_inv_std_.array();
  return x.cwiseMax(-RunningNormalizer::kClip).cwiseMin(RunningNormalizer::kClip);
}

RowMatrix FastActor::run_body(const std::vector<Layer>& body, RowMatrix x) const {
  for (const auto& l : body) {
    const RowMatrix z = (x * l.weight).rowwise() + l.bias;
    activate(activation_, z, x);
  }
  return x;
}

Eigen::VectorXf FastActor::value(const RowMatrix& obs) const {
  if (!with_critic_) return Eigen::VectorXf::Zero(obs.rows());
  RowMatrix x = normalized(obs);
  RowMatrix h = run_body(shared_critic_ ? actor_body_ : critic_body_, x);
  return ((h * value_head_.weight).rowwise() + value_head_.bias).col(0);
}

void FastActor::act(const RowMatrix& obs, const uint8_t* mask, bool deterministic,
                    std::mt19937_64& rng, ActBatch& out) const {
  const int64_t batch = obs.rows();
  RowMatrix x = normalized(obs);
  RowMatrix h = run_body(actor_body_, x);
  out.log_prob.setZero(batch);
  // continuous part: Gaussian around the mean head
  const int c = action_.continuous_size;
  out.continuous.resize(batch, c);
  if (c > 0) {
    RowMatrix mean = (h * mean_head_.weight).rowwise() + mean_head_.bias;
    const double half_log_2pi = 0.5 * std::log(2.0 * M_PI);
    for (int64_t b = 0; b < batch; ++b)
      for (int j = 0; j < c; ++j) {
        const double z = deterministic ? 0.0 : standard_normal(rng);
        out.continuous(b, j) = float(mean(b, j) + z * std::exp(double(log_std_[j])));
        out.log_prob[b] += float(-0.5 * z * z - log_std_[j] - half_log_2pi);
      }
  }
  // discrete part: one masked categorical per branch
  const int k = action_.num_branches();
  out.discrete.resize(batch, k);
  if (k > 0) {
    RowMatrix logits = (h * logits_head_.weight).rowwise() + logits_head_.bias;
    const int m = action_.mask_size();
    for (int64_t b = 0; b < batch; ++b) {
      int offset = 0;
      for (int br = 0; br < k; ++br) {
        const int n = action_.discrete_branches[br];
        const uint8_t* allowed = mask ? mask + b * m + offset : nullptr;
        double top = -INFINITY;
        for (int o = 0; o < n; ++o)
          if (!allowed || allowed[o]) top = std::max(top, double(logits(b, offset + o)));
        double total = 0;
        for (int o = 0; o < n; ++o)
          if (!allowed || allowed[o]) total += std::exp(double(logits(b, offset + o)) - top);
        int choice = -1;
        if (deterministic) {
          for (int o = 0; o < n; ++o)
            if ((!allowed || allowed[o]) && (choice < 0 || logits(b, offset + o) > logits(b, offset + choice)))
              choice = o;
        } else {
          double u = uniform01(rng) * total;
          for (int o = 0; o < n; ++o) {
            if (allowed && !allowed[o]) continue;
            choice = o;
            u -= std::exp(double(logits(b, offset + o)) - top);
            if (u < 0) break;
          }
        }
        out.discrete(b, br) = choice;
        out.log_prob[b] += float(double(logits(b, offset + choice)) - top - std::log(total));
        offset += n;
      }
    }
  }
  // critic
  if (!with_critic_) {
    out.value.setZero(batch);
    return;
  }
  RowMatrix hv = shared_critic_ ? h : run_body(critic_body_, x);
  out.value = ((hv * value_head_.weight).rowwise() + value_head_.bias).col(0);
}

}  // namespace rlt
