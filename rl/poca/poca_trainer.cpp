#include "rl/poca/poca_trainer.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "rl/core/action_distribution.h"
#include "rl/core/bad_numbers.h"
#include "rl/core/lambda_return.h"

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
  actor_gradient_ = std::make_unique<MlpPpoGradient>(*net_);
  critic_gradient_ = std::make_unique<PocaCriticGradient>(*critic_);
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
  auto old_value = torch::from_blob(buffer_.value.data(), {n});                              // [N]
  auto returns = torch::from_blob(buffer_.returns.data(), {n});                              // [N]
  // the actor's rows as MinibatchView reads them (it has no critic: the last two are unused)
  auto actor_old = torch::stack({torch::from_blob(buffer_.log_prob.data(), {n}), adv,
                                 old_value, returns}, 1);                                  // [N, 4]
  auto critic_old = torch::stack({old_value, torch::from_blob(buffer_.baseline.data(), {n}),
                                  returns}, 1);                                            // [N, 3]

  const int64_t bs = local_batch_size(), batches = agreed_batches(n);  // this rank's share
  double sums[6] = {0, 0, 0, 0, 0, 0};  // policy, value, baseline, entropy, KL, clip fraction
  for (int epoch = 0; epoch < hp.num_epoch; ++epoch) {
    auto perm = permutation(n);
    auto idx = torch::from_blob(perm.data(), {n}, torch::kInt64);
    for (int64_t b = 0; b < batches; ++b) {
      // each minibatch gathers its rows (a whole shuffled copy of the others' observations
      // would be N x U x D floats, hundreds of MB, allocated and faulted in every epoch)
      auto mb_idx = idx.narrow(0, b * bs, bs);                                   // [B]
      auto slice = [&](const torch::Tensor& t) { return t.index_select(0, mb_idx).contiguous(); };
      auto mb_obs = normalize(slice(obs)).contiguous();                          // [B, D]
      auto mb_others = normalize(slice(others)).contiguous();                    // [B, U, D]
      auto mb_actions = slice(actions);                                          // [B, U, A]
      auto mb_present = slice(present);                                          // [B, U]
      auto mb_actor_old = slice(actor_old), mb_critic_old = slice(critic_old);   // [B, 4], [B, 3]
      torch::Tensor mb_cont, mb_disc, mb_mask;  // [B, C], [B, K], [B, M] where the action has them
      MinibatchView actor_mb;
      actor_mb.rows = bs;
      actor_mb.obs = mb_obs.data_ptr<float>();
      if (s.continuous_size) actor_mb.continuous = (mb_cont = slice(cont)).data_ptr<float>();
      if (s.num_branches()) actor_mb.discrete = (mb_disc = slice(disc)).data_ptr<int64_t>();
      if (s.mask_size()) actor_mb.mask = (mb_mask = slice(mask)).data_ptr<float>();
      actor_mb.old = mb_actor_old.data_ptr<float>();
      CriticMinibatchView critic_mb;
      critic_mb.rows = bs;
      critic_mb.others = used;
      critic_mb.obs = actor_mb.obs;
      critic_mb.others_obs = mb_others.data_ptr<float>();
      critic_mb.others_actions = mb_actions.data_ptr<float>();
      critic_mb.others_present = mb_present.data_ptr<float>();
      critic_mb.old = mb_critic_old.data_ptr<float>();

      // each writes its own parameters' gradients: the actor's, then the critic's
      const LossValues l = actor_gradient_->compute(actor_mb, stats.epsilon, stats.beta,
                                                    stats.discrete_beta, kValueCoef);
      const CriticLossValues critic_loss =
          critic_gradient_->compute(critic_mb, stats.epsilon, kValueCoef, kBaselineCoef);
      const double total = l.total + kValueCoef * critic_loss.value +
                           kBaselineCoef * critic_loss.baseline;
      if (!std::isfinite(total)) {
        std::ostringstream os;
        os << "behavior " << spec_.name << ", update " << updates_ + 1 << ", step " << step_
           << ": loss is " << total << " (policy " << l.policy << ", value " << critic_loss.value
           << ", baseline " << critic_loss.baseline << ", entropy " << l.entropy << ")";
        throw BadNumberError(os.str());
      }
      reduce_gradients();
      if (hp.max_grad_norm > 0) optimizer_->clip_grad_norm(hp.max_grad_norm);
      optimizer_->step(stats.learning_rate);
      sums[0] += l.policy;
      sums[1] += critic_loss.value;
      sums[2] += critic_loss.baseline;
      sums[3] += l.entropy;
      sums[4] += l.approx_kl;
      sums[5] += l.clip_fraction;
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
    // critic (as PocaCriticGradient computes it): the observation embedding of the own and U
    // others' observations, the (observation, action) embedding of the U others, the query, key
    // and value projections of these 1 + 2U entities, then for the value's and the baseline's
    // 1 + U members each the out projection, and the MLP and the head for both
    const double d = obs_size_, h = shape_hidden(), a = action_code_, u = double(used);
    const int layers = config_.network_settings.num_layers;
    const double tail = layers * h * h + h;
    const double embeddings = (1 + u) * d * h + u * (d + a) * h;
    const double critic = embeddings + 3 * (1 + 2 * u) * h * h + 2 * ((1 + u) * h * h + tail);
    stats.matmul_flops =
        matmul_flops_per_experience(actor_macs() + critic, actor_input_macs() + embeddings) *
        double(batches * bs) * hp.num_epoch;
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
