#include "rl/ppo/ppo_trainer.h"

#include <cmath>
#include <sstream>

#include "rl/core/bad_numbers.h"
#include "rl/core/gae.h"

namespace rlt {

PpoTrainer::PpoTrainer(const BehaviorSpec& spec, const BehaviorConfig& config, int rows,
                       uint64_t seed, const std::string& env_name)
    : OnPolicyTrainer(spec, config, rows, seed, env_name, /*with_critic=*/true) {
  create_optimizer();
  gradient_ = std::make_unique<MlpPpoGradient>(*net_);
}

void PpoTrainer::end_trajectories(const BehaviorBuffers& buf, const std::vector<int>& terminated,
                                  const std::vector<int>& bootstrapped) {
  for (int r : terminated) finish(r, 0.f);
  if (bootstrapped.empty()) return;
  // one critic pass for every trajectory that ends with a bootstrap (with the normalizer as
  // updated by the trajectories that just ended)
  if (actor_stale_) refresh_actor();
  RowMatrix obs;
  gather_obs(buf, bootstrapped, obs, "final observation");
  Eigen::VectorXf v = actor_.value(obs);
  for (size_t i = 0; i < bootstrapped.size(); ++i) finish(bootstrapped[i], v[i]);
}

void PpoTrainer::finish(int row, float bootstrap_value) {
  auto& t = trajectories_[row];
  auto& rewards = rewards_[row];
  const int64_t n = int64_t(rewards.size());
  t.advantages.resize(n);
  t.returns.resize(n);
  compute_gae(rewards.data(), t.value.data(), n, bootstrap_value, config_.extrinsic.gamma,
              config_.hyperparameters.lambd, t.advantages.data(), t.returns.data());
  fold_observations(t.obs.data(), n);
  buffer_.append(t);
  t.clear();
  rewards.clear();
}

UpdateStats PpoTrainer::update() {
  const auto& hp = config_.hyperparameters;
  UpdateStats stats;
  const int64_t n = buffer_.size();
  stats.experiences = n;
  fill_schedules(stats);
  sync_normalizer();

  // the buffer as tensors (no copy), observations normalized once
  const auto& s = spec_.action;
  auto obs = normalize(torch::from_blob(buffer_.obs.data(), {n, obs_size_}));  // [N, D]
  auto cont = torch::from_blob(buffer_.continuous.data(), {n, s.continuous_size});   // [N, C]
  auto disc = torch::from_blob(buffer_.discrete.data(), {n, s.num_branches()}, torch::kInt64);
  auto mask = torch::from_blob(buffer_.mask.data(), {n, s.mask_size()});            // [N, M]
  auto old_log_prob = torch::from_blob(buffer_.log_prob.data(), {n});               // [N]
  auto old_value = torch::from_blob(buffer_.value.data(), {n});                     // [N]
  auto returns = torch::from_blob(buffer_.returns.data(), {n});                     // [N]
  auto adv = torch::from_blob(buffer_.advantages.data(), {n});                      // [N]
  adv = normalize_advantages(adv);

  const int64_t bs = local_batch_size();  // batch_size, or this rank's share of it
  const int64_t batches = agreed_batches(n);
  double sum_policy = 0, sum_value = 0, sum_entropy = 0, sum_kl = 0, sum_clipped = 0;
  for (int epoch = 0; epoch < hp.num_epoch; ++epoch) {
    // one gather per tensor and epoch; minibatches are slices
    auto perm = permutation(n);
    auto idx = torch::from_blob(perm.data(), {n}, torch::kInt64);
    auto e_obs = obs.index_select(0, idx);                                           // [N, D]
    auto e_mask = s.mask_size() ? mask.index_select(0, idx) : torch::Tensor();       // [N, M]
    auto e_cont = s.continuous_size ? cont.index_select(0, idx) : torch::Tensor();   // [N, C]
    auto e_disc = s.num_branches() ? disc.index_select(0, idx) : torch::Tensor();    // [N, K]
    auto e_old = torch::stack({old_log_prob, adv, old_value, returns}, 1).index_select(0, idx);  // [N, 4]
    for (int64_t b = 0; b < batches; ++b) {
      MinibatchView mb;
      mb.rows = bs;
      mb.obs = e_obs.data_ptr<float>() + b * bs * obs_size_;
      if (s.continuous_size) mb.continuous = e_cont.data_ptr<float>() + b * bs * s.continuous_size;
      if (s.num_branches()) mb.discrete = e_disc.data_ptr<int64_t>() + b * bs * s.num_branches();
      if (s.mask_size()) mb.mask = e_mask.data_ptr<float>() + b * bs * s.mask_size();
      mb.old = e_old.data_ptr<float>() + b * bs * 4;

      const LossValues l = gradient_->compute(mb, stats.epsilon, stats.beta, stats.discrete_beta,
                                                  hp.value_loss_coef);
      if (!std::isfinite(l.total)) {
        std::ostringstream os;
        os << "behavior " << spec_.name << ", update " << updates_ + 1 << ", step " << step_
           << ": loss is " << l.total << " (policy " << l.policy << ", value " << l.value
           << ", entropy " << l.entropy << ")";
        throw BadNumberError(os.str());
      }
      reduce_gradients();
      if (hp.max_grad_norm > 0) optimizer_->clip_grad_norm(hp.max_grad_norm);
      optimizer_->step(stats.learning_rate);
      sum_policy += l.policy;
      sum_value += l.value;
      sum_entropy += l.entropy;
      sum_kl += l.approx_kl;
      sum_clipped += l.clip_fraction;
    }
  }
  const double count = std::max<int64_t>(1, batches * hp.num_epoch);
  stats.policy_loss = float(sum_policy / count);
  stats.value_loss = float(sum_value / count);
  stats.entropy = float(sum_entropy / count);
  stats.approx_kl = float(sum_kl / count);
  stats.clip_fraction = float(sum_clipped / count);
  const double input_macs = actor_input_macs() * (hp.shared_critic ? 1 : 2);  // both bodies
  stats.matmul_flops = matmul_flops_per_experience(actor_macs() + ppo_critic_macs(), input_macs) *
                       double(batches * bs) * hp.num_epoch;
  buffer_.clear();
  ++updates_;
  actor_stale_ = true;
  return stats;
}

}  // namespace rlt
