#include "rl/poca/poca_trainer.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "rl/core/action_distribution.h"
#include "rl/core/bad_numbers.h"
#include "rl/core/lambda_return.h"
#include "rl/ppo/ppo_loss.h"

namespace rlt {

PocaTrainer::PocaTrainer(const BehaviorSpec& spec, const BehaviorConfig& config, int rows,
                         uint64_t seed, const std::string& env_name)
    : OnPolicyTrainer(spec, config, rows, seed, env_name, /*with_critic=*/false),
      critic_(nullptr),
      others_(spec.agent_slots - 1),
      action_code_(spec.action.continuous_size + spec.action.mask_size()) {
  PocaCriticShape shape;
  shape.obs_size = obs_size_;
  shape.action_size = action_code_;
  shape.hidden_units = config.network_settings.hidden_units;
  shape.num_layers = config.network_settings.num_layers;
  shape.activation = config.network_settings.activation;
  critic_ = PocaCritic(shape);
  create_optimizer();
  buffer_.others = others_;
  buffer_.action_code = action_code_;
  trajectories_.assign(rows_, buffer_);
}

template <typename Pred>
std::vector<int> PocaTrainer::groupmates(const BehaviorBuffers& buf, int row, Pred member) const {
  const int slots = spec_.agent_slots, first = row - row % slots;
  std::vector<int> out;
  out.reserve(others_);
  for (int r = first; r < first + slots; ++r) {
    if (r == row) continue;
    const bool mate = buf.group_id[r] == buf.group_id[row] && member(buf.step_type[r]);
    out.push_back(mate ? r : -1);
  }
  return out;
}

int64_t PocaTrainer::packed_others(const std::vector<float>& present, int64_t n) const {
  int64_t used = 0;  // slots are packed (present first), so the count of the fullest row
  for (int64_t i = 0; i < n; ++i) {
    int64_t k = 0;
    while (k < others_ && present[size_t(i) * others_ + k] != 0.f) ++k;
    used = std::max(used, k);
  }
  return used;
}

void PocaTrainer::encode_action(const BehaviorBuffers& buf, int row, float* out) const {
  const auto& a = spec_.action;
  const int c = a.continuous_size, k = a.num_branches();
  for (int j = 0; j < c; ++j) out[j] = buf.continuous_actions[size_t(row) * c + j];
  std::fill(out + c, out + c + a.mask_size(), 0.f);
  int offset = c;
  for (int j = 0; j < k; ++j) {
    out[offset + buf.discrete_actions[size_t(row) * k + j]] = 1.f;
    offset += a.discrete_branches[j];
  }
}

void PocaTrainer::on_acted(const BehaviorBuffers& buf, const std::vector<int>& rows) {
  RowMatrix mate_obs;
  std::vector<float> code(action_code_);
  for (int r : rows) {
    auto mates = groupmates(buf, r, needs_action);
    std::vector<int> present_rows;
    for (int m : mates)
      if (m >= 0) present_rows.push_back(m);
    gather_obs(buf, present_rows, mate_obs, "observation");
    // present groupmates first, then the empty slots: the critic is invariant to the order of
    // the members, and packed slots let it skip the slots no sample uses (packed_others)
    auto& t = trajectories_[r];
    for (size_t next = 0; next < present_rows.size(); ++next) {
      const float* o = mate_obs.data() + next * obs_size_;
      t.others_obs.insert(t.others_obs.end(), o, o + obs_size_);
      encode_action(buf, present_rows[next], code.data());
      t.others_action.insert(t.others_action.end(), code.begin(), code.end());
      t.others_present.push_back(1.f);
    }
    for (size_t k = present_rows.size(); k < size_t(others_); ++k) {
      t.others_obs.insert(t.others_obs.end(), obs_size_, 0.f);
      t.others_action.insert(t.others_action.end(), action_code_, 0.f);
      t.others_present.push_back(0.f);
    }
  }
}

float PocaTrainer::step_reward(const BehaviorBuffers& buf, int row) const {
  float reward = buf.reward[row] + buf.group_reward[row];
  for (int m : groupmates(buf, row, [](StepType t) { return t == StepType::kMid || t == StepType::kLast; }))
    if (m >= 0) reward += buf.reward[m];
  return reward * config_.extrinsic.strength;
}

void PocaTrainer::end_trajectories(const BehaviorBuffers& buf, const std::vector<int>& terminated,
                                   const std::vector<int>& bootstrapped) {
  for (int r : terminated) finish(buf, r, true);
  for (int r : bootstrapped) finish(buf, r, false);
}

void PocaTrainer::finish(const BehaviorBuffers& buf, int row, bool terminal) {
  auto& t = trajectories_[row];
  auto& rewards = rewards_[row];
  const int64_t n = int64_t(rewards.size());
  fold_observations(t.obs.data(), n);
  torch::NoGradGuard no_grad;
  // group value and counterfactual baseline of every step
  const int64_t used = packed_others(t.others_present, n);  // the slots after these are empty
  auto own = normalize(torch::from_blob(t.obs.data(), {n, obs_size_}));                  // [T, D]
  auto others = normalize(torch::from_blob(t.others_obs.data(), {n, others_, obs_size_})
                              .narrow(1, 0, used));                                          // [T, U, D]
  auto actions = torch::from_blob(t.others_action.data(), {n, others_, action_code_})
                     .narrow(1, 0, used);                                                    // [T, U, A]
  auto present = torch::from_blob(t.others_present.data(), {n, others_}).narrow(1, 0, used);  // [T, U]
  auto all = torch::cat({own.unsqueeze(1), others}, 1);                                   // [T, N, D]
  auto all_present = torch::cat({torch::ones({n, 1}), present}, 1);                       // [T, N]
  auto values = critic_->value(all, all_present).contiguous();                            // [T]
  auto baselines = critic_->baseline(own, others, actions, present).contiguous();         // [T]

  // bootstrap: 0 only when the whole group is done and this agent terminated
  const auto alive = groupmates(buf, row, needs_action);
  const bool group_done = std::all_of(alive.begin(), alive.end(), [](int m) { return m < 0; });
  float bootstrap = 0.f;
  if (!(terminal && group_done)) {
    std::vector<int> members = {row};
    for (int m : groupmates(buf, row, [](StepType s) { return s != StepType::kAbsent; }))
      if (m >= 0) members.push_back(m);
    const int64_t count = int64_t(members.size());
    RowMatrix next;
    gather_obs(buf, members, next, "final observation");
    auto next_obs = normalize(torch::from_blob(next.data(), {1, count, obs_size_}));  // [1, M, D]
    bootstrap = critic_->value(next_obs, torch::ones({1, count})).item<float>();
  }
  t.value.assign(values.data_ptr<float>(), values.data_ptr<float>() + n);
  t.baseline.assign(baselines.data_ptr<float>(), baselines.data_ptr<float>() + n);
  t.returns.resize(n);
  compute_lambda_returns(rewards.data(), t.value.data(), n, bootstrap, config_.extrinsic.gamma,
                         config_.hyperparameters.lambd, t.returns.data());
  t.advantages.resize(n);
  for (int64_t i = 0; i < n; ++i) t.advantages[i] = t.returns[i] - t.baseline[i];
  buffer_.append(t);
  t.clear();
  rewards.clear();
}

UpdateStats PocaTrainer::update() {
  const auto& hp = config_.hyperparameters;
  const auto& s = spec_.action;
  UpdateStats stats;
  const int64_t n = buffer_.size();
  stats.experiences = n;
  fill_schedules(stats);
  sync_normalizer();

  // the buffer as tensors
  // only the member slots some experience uses (U <= O; slots are packed, present first)
  const int64_t used = packed_others(buffer_.others_present, n);
  // observations are normalized per minibatch (a normalized copy of the buffer is hundreds of MB)
  auto obs = torch::from_blob(buffer_.obs.data(), {n, obs_size_});                           // [N, D]
  auto others = torch::from_blob(buffer_.others_obs.data(), {n, others_, obs_size_})
                    .narrow(1, 0, used);                                                    // [N, U, D]
  auto actions = torch::from_blob(buffer_.others_action.data(), {n, others_, action_code_})
                     .narrow(1, 0, used);                                                   // [N, U, A]
  auto present = torch::from_blob(buffer_.others_present.data(), {n, others_})
                     .narrow(1, 0, used);                                                   // [N, U]
  auto cont = torch::from_blob(buffer_.continuous.data(), {n, s.continuous_size});             // [N, C]
  auto disc = torch::from_blob(buffer_.discrete.data(), {n, s.num_branches()}, torch::kInt64); // [N, K]
  auto mask = torch::from_blob(buffer_.mask.data(), {n, s.mask_size()});                       // [N, M]
  auto adv = torch::from_blob(buffer_.advantages.data(), {n});                                 // [N]
  adv = normalize_advantages(adv);
  auto old = torch::stack({torch::from_blob(buffer_.log_prob.data(), {n}), adv,
                           torch::from_blob(buffer_.value.data(), {n}),
                           torch::from_blob(buffer_.baseline.data(), {n}),
                           torch::from_blob(buffer_.returns.data(), {n})},
                          1);  // [N, 5]

  const int64_t bs = local_batch_size(), batches = agreed_batches(n);  // this rank's share
  double sums[6] = {0, 0, 0, 0, 0, 0};  // policy, value, baseline, entropy, KL, clip fraction
  for (int epoch = 0; epoch < hp.num_epoch; ++epoch) {
    auto perm = permutation(n);
    auto idx = torch::from_blob(perm.data(), {n}, torch::kInt64);
    for (int64_t b = 0; b < batches; ++b) {
      // each minibatch gathers its rows (a whole shuffled copy of the others' observations
      // would be N x U x D floats, hundreds of MB, allocated and faulted in every epoch)
      auto mb_idx = idx.narrow(0, b * bs, bs);                                   // [B]
      auto slice = [&](const torch::Tensor& t) { return t.index_select(0, mb_idx); };
      auto mb_obs = normalize(slice(obs)), mb_others = normalize(slice(others));  // [B, D], [B, U, D]
      auto mb_present = slice(present);                                          // [B, U]
      auto mb_old = slice(old);                                                  // [B, 5]
      auto e_mask = mask, e_cont = cont, e_disc = disc, e_actions = actions;
      auto out = net_->actor(mb_obs);
      auto lp = evaluate_actions(s, out.mean, net_->log_std, out.logits,
                                 s.mask_size() ? slice(e_mask) : torch::Tensor(),
                                 s.continuous_size ? slice(e_cont) : torch::Tensor(),
                                 s.num_branches() ? slice(e_disc) : torch::Tensor());
      auto all = torch::cat({mb_obs.unsqueeze(1), mb_others}, 1);
      auto all_present = torch::cat({torch::ones({bs, 1}), mb_present}, 1);
      auto values = critic_->value(all, all_present);
      auto baselines = critic_->baseline(mb_obs, mb_others, slice(e_actions), mb_present);
      auto returns = mb_old.select(1, 4);
      PpoLoss l = ppo_loss(lp.log_prob, mb_old.select(1, 0), mb_old.select(1, 1), values,
                           mb_old.select(1, 2), returns, lp.entropy, lp.discrete_entropy,
                           stats.epsilon, stats.beta, stats.discrete_beta, 0.5f);
      auto baseline_loss = clipped_value_loss(baselines, mb_old.select(1, 3), returns, stats.epsilon);
      auto total = l.total + 0.25f * baseline_loss;  // policy + 0.5 (value + 0.5 baseline) - beta H
      const float total_value = total.item<float>();
      if (!std::isfinite(total_value)) {
        std::ostringstream os;
        os << "behavior " << spec_.name << ", update " << updates_ + 1 << ", step " << step_
           << ": loss is " << total_value << " (policy " << l.policy.item<float>() << ", value "
           << l.value.item<float>() << ", baseline " << baseline_loss.item<float>() << ")";
        throw BadNumberError(os.str());
      }
      optimizer_->zero_grad();
      total.backward();
      reduce_gradients();
      if (hp.max_grad_norm > 0) optimizer_->clip_grad_norm(hp.max_grad_norm);
      optimizer_->step(stats.learning_rate);
      sums[0] += l.policy.item<float>();
      sums[1] += l.value.item<float>();
      sums[2] += baseline_loss.item<float>();
      sums[3] += l.entropy.item<float>();
      sums[4] += l.approx_kl.item<float>();
      sums[5] += l.clip_fraction.item<float>();
    }
  }
  const double count = std::max<int64_t>(1, batches * hp.num_epoch);
  stats.policy_loss = float(sums[0] / count);
  stats.value_loss = float(sums[1] / count);
  stats.baseline_loss = float(sums[2] / count);
  stats.entropy = float(sums[3] / count);
  stats.approx_kl = float(sums[4] / count);
  stats.clip_fraction = float(sums[5] / count);
  {
    // critic: value over 1 + U members, baseline over the own observation and U (obs, action)
    // pairs; each with embeddings, 4 attention projections per member, the MLP and the head
    const double d = obs_size_, h = shape_hidden(), a = action_code_, u = double(used);
    const int layers = config_.network_settings.num_layers;
    const double tail = layers * h * h + h;
    const double value = (1 + u) * (d * h + 4 * h * h) + tail;
    const double baseline = d * h + u * (d + a) * h + (1 + u) * 4 * h * h + tail;
    stats.matmul_flops = 6.0 * (actor_macs() + value + baseline) * double(batches * bs) * hp.num_epoch;
  }
  buffer_.clear();
  ++updates_;
  actor_stale_ = true;
  return stats;
}

double PocaTrainer::shape_hidden() const { return critic_->shape().hidden_units; }

void PocaTrainer::save_extra(torch::serialize::OutputArchive& archive) const {
  torch::serialize::OutputArchive critic;
  critic_->save(critic);
  archive.write("critic", critic);
}

void PocaTrainer::load_extra(torch::serialize::InputArchive& archive) {
  torch::serialize::InputArchive critic;
  archive.read("critic", critic);
  critic_->load(critic);
}

}  // namespace rlt
