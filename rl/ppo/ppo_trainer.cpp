#include "rl/ppo/ppo_trainer.h"

#include <cmath>
#include <numeric>
#include <sstream>

#include "rl/core/action_distribution.h"
#include "rl/core/archive_io.h"
#include "rl/core/bad_numbers.h"
#include "rl/core/gae.h"
#include "rl/ppo/mlp_ppo_gradient.h"

namespace rlt {

namespace {
int total_obs_size(const BehaviorSpec& spec) {
  int n = 0;
  for (const auto& o : spec.observations) n += o.size();
  return n;
}
}  // namespace

PpoTrainer::PpoTrainer(const BehaviorSpec& spec, const BehaviorConfig& config, int rows,
                       uint64_t seed, const std::string& env_name)
    : spec_(spec),
      config_(config),
      env_name_(env_name),
      rows_(rows),
      obs_size_(total_obs_size(spec)),
      net_(nullptr),
      normalizer_(total_obs_size(spec)),
      rng_(seed) {
  NetworkShape shape;
  shape.obs_size = obs_size_;
  shape.action = spec.action;
  shape.hidden_units = config.network_settings.hidden_units;
  shape.num_layers = config.network_settings.num_layers;
  shape.activation = config.network_settings.activation;
  shape.shared_critic = config.hyperparameters.shared_critic;
  net_ = PolicyNetwork(shape);
  optimizer_ = std::make_unique<FlatAdam>(net_->parameters());
  gradient_ = std::make_unique<MlpPpoGradient>(*net_);

  pending_.assign(rows, 0);
  trajectories_.resize(rows);
  rewards_.resize(rows);
  episode_return_.assign(rows, 0.0);
  episode_length_.assign(rows, 0);
  for (auto* b : {&buffer_}) {
    b->obs_size = obs_size_;
    b->continuous_size = spec.action.continuous_size;
    b->num_branches = spec.action.num_branches();
    b->mask_size = spec.action.mask_size();
  }
  for (auto& t : trajectories_) t = buffer_;
}

std::string PpoTrainer::where(const BehaviorBuffers& buf, int row) const {
  std::ostringstream os;
  os << "environment " << env_name_ << ", instance " << row / spec_.agent_slots << ", behavior "
     << spec_.name << ", agent " << buf.agent_id[row] << ", step " << step_;
  return os.str();
}

void PpoTrainer::gather_obs(const BehaviorBuffers& buf, const std::vector<int>& rows,
                            RowMatrix& out, const char* what) const {
  out.resize(int64_t(rows.size()), obs_size_);
  for (size_t i = 0; i < rows.size(); ++i) {
    float* dst = out.data() + i * obs_size_;
    for (size_t k = 0; k < spec_.observations.size(); ++k) {
      const int n = spec_.observations[k].size();
      const float* src = buf.observations[k].data() + size_t(rows[i]) * n;
      if (first_non_finite(src, n) >= 0)
        require_finite(src, n, where(buf, rows[i]) + ": " + what + " '" +
                                   spec_.observations[k].name + "'");
      std::memcpy(dst, src, sizeof(float) * n);
      dst += n;
    }
  }
}

void PpoTrainer::refresh_actor() {
  actor_.copy_from(*net_, normalizer());
  actor_stale_ = false;
}

void PpoTrainer::act(BehaviorBuffers& buf) {
  if (actor_stale_) refresh_actor();
  act_rows_.clear();
  for (int r = 0; r < rows_; ++r)
    if (needs_action(buf.step_type[r])) act_rows_.push_back(r);
  if (act_rows_.empty()) return;
  gather_obs(buf, act_rows_, act_obs_, "observation");
  const int m = spec_.action.mask_size();
  // masks of the acting rows, contiguous
  std::vector<uint8_t> masks(act_rows_.size() * m);
  for (size_t i = 0; i < act_rows_.size(); ++i)
    std::memcpy(masks.data() + i * m, buf.action_mask.data() + size_t(act_rows_[i]) * m, m);
  actor_.act(act_obs_, m ? masks.data() : nullptr, config_.network_settings.deterministic, rng_,
             act_out_);

  const int c = spec_.action.continuous_size, k = spec_.action.num_branches();
  for (size_t i = 0; i < act_rows_.size(); ++i) {
    const int r = act_rows_[i];
    // actions for the env
    for (int j = 0; j < c; ++j)
      buf.continuous_actions[size_t(r) * c + j] = clip_continuous_action(act_out_.continuous(i, j));
    for (int j = 0; j < k; ++j) buf.discrete_actions[size_t(r) * k + j] = act_out_.discrete(i, j);
    // the experience, completed by observe()
    auto& t = trajectories_[r];
    if (buf.step_type[r] == StepType::kFirst) {
      episode_return_[r] = 0.0;
      episode_length_[r] = 0;
    }
    t.obs.insert(t.obs.end(), act_obs_.data() + i * obs_size_, act_obs_.data() + (i + 1) * obs_size_);
    for (int j = 0; j < c; ++j) t.continuous.push_back(act_out_.continuous(i, j));
    for (int j = 0; j < k; ++j) t.discrete.push_back(act_out_.discrete(i, j));
    for (int j = 0; j < m; ++j) t.mask.push_back(masks[i * m + j]);
    t.log_prob.push_back(act_out_.log_prob[i]);
    t.value.push_back(act_out_.value[i]);
    pending_[r] = 1;
  }
  step_ += int64_t(act_rows_.size());
}

void PpoTrainer::observe(const BehaviorBuffers& buf) {
  const float strength = config_.extrinsic.strength;
  std::vector<int> bootstrap_rows;
  for (int r = 0; r < rows_; ++r) {
    if (!pending_[r]) continue;
    pending_[r] = 0;
    const StepType st = buf.step_type[r];
    const float reward = buf.reward[r] + buf.group_reward[r];
    if (!std::isfinite(reward)) require_finite(&reward, 1, where(buf, r) + ": reward");
    rewards_[r].push_back(reward * strength);
    episode_return_[r] += buf.reward[r];
    episode_length_[r] += 1;
    if (st == StepType::kLast) {
      episode_stats_.returns.push_back(float(episode_return_[r]));
      episode_stats_.lengths.push_back(float(episode_length_[r]));
      if (buf.terminated[r])
        end_trajectory(r, 0.f);
      else
        bootstrap_rows.push_back(r);
    } else if (int(rewards_[r].size()) >= config_.time_horizon) {
      bootstrap_rows.push_back(r);
    }
  }
  if (bootstrap_rows.empty()) return;
  // one critic pass for every trajectory that ends with a bootstrap
  if (actor_stale_) refresh_actor();
  RowMatrix obs;
  gather_obs(buf, bootstrap_rows, obs, "final observation");
  Eigen::VectorXf v = actor_.value(obs);
  for (size_t i = 0; i < bootstrap_rows.size(); ++i) end_trajectory(bootstrap_rows[i], v[i]);
}

void PpoTrainer::interrupt_all(const BehaviorBuffers& buf) {
  std::vector<int> rows;
  for (int r = 0; r < rows_; ++r)
    if (!rewards_[r].empty()) rows.push_back(r);
  if (rows.empty()) return;
  if (actor_stale_) refresh_actor();
  RowMatrix obs;
  gather_obs(buf, rows, obs, "observation");
  Eigen::VectorXf v = actor_.value(obs);
  for (size_t i = 0; i < rows.size(); ++i) {
    // an unanswered decision (acted, env not stepped) is dropped
    auto& t = trajectories_[rows[i]];
    const int64_t keep = int64_t(rewards_[rows[i]].size());
    t.obs.resize(keep * obs_size_);
    t.continuous.resize(keep * spec_.action.continuous_size);
    t.discrete.resize(keep * spec_.action.num_branches());
    t.mask.resize(keep * spec_.action.mask_size());
    t.log_prob.resize(keep);
    t.value.resize(keep);
    pending_[rows[i]] = 0;
    end_trajectory(rows[i], v[i]);
  }
}

void PpoTrainer::end_trajectory(int row, float bootstrap_value) {
  auto& t = trajectories_[row];
  auto& rewards = rewards_[row];
  const int64_t n = int64_t(rewards.size());
  t.advantages.resize(n);
  t.returns.resize(n);
  compute_gae(rewards.data(), t.value.data(), n, bootstrap_value, config_.extrinsic.gamma,
              config_.hyperparameters.lambd, t.advantages.data(), t.returns.data());
  if (config_.network_settings.normalize) {
    normalizer_.update(t.obs.data(), n);
    actor_stale_ = true;
  }
  buffer_.append(t);
  t.clear();
  rewards.clear();
}

float PpoTrainer::decayed(float initial, float minimum, Schedule schedule) const {
  if (schedule == Schedule::kConstant) return initial;
  const double frac = std::min(1.0, double(step_) / double(config_.max_steps));
  return float(std::max(double(minimum), initial - (initial - minimum) * frac));
}

UpdateStats PpoTrainer::update() {
  const auto& hp = config_.hyperparameters;
  UpdateStats stats;
  const int64_t n = buffer_.size();
  stats.experiences = n;
  stats.learning_rate = decayed(hp.learning_rate, 1e-10f, hp.learning_rate_schedule);
  stats.epsilon = decayed(hp.epsilon, 0.1f, hp.epsilon_schedule.value_or(hp.learning_rate_schedule));
  stats.beta = decayed(hp.beta, 1e-5f, hp.beta_schedule.value_or(hp.learning_rate_schedule));

  // the buffer as tensors (no copy), observations normalized once
  const auto& s = spec_.action;
  auto obs = torch::from_blob(buffer_.obs.data(), {n, obs_size_});  // [N, D]
  if (config_.network_settings.normalize) {
    auto mean = torch::tensor(normalizer_.mean_float());     // [D]
    auto inv = torch::tensor(normalizer_.inverse_std());     // [D]
    obs = ((obs - mean) * inv).clamp(-RunningNormalizer::kClip, RunningNormalizer::kClip);
  }
  auto cont = torch::from_blob(buffer_.continuous.data(), {n, s.continuous_size});   // [N, C]
  auto disc = torch::from_blob(buffer_.discrete.data(), {n, s.num_branches()}, torch::kInt64);
  auto mask = torch::from_blob(buffer_.mask.data(), {n, s.mask_size()});            // [N, M]
  auto old_log_prob = torch::from_blob(buffer_.log_prob.data(), {n});               // [N]
  auto old_value = torch::from_blob(buffer_.value.data(), {n});                     // [N]
  auto returns = torch::from_blob(buffer_.returns.data(), {n});                     // [N]
  auto adv = torch::from_blob(buffer_.advantages.data(), {n});                      // [N]
  adv = (adv - adv.mean()) / (adv.std() + 1e-10f);

  const int64_t bs = hp.batch_size;
  const int64_t batches = n / bs;
  std::vector<int64_t> perm(n);
  double sum_policy = 0, sum_value = 0, sum_entropy = 0;
  for (int epoch = 0; epoch < hp.num_epoch; ++epoch) {
    // Fisher-Yates with our own engine, then one gather per tensor; minibatches are slices
    std::iota(perm.begin(), perm.end(), 0);
    for (int64_t i = n - 1; i > 0; --i) std::swap(perm[i], perm[int64_t(uniform01(rng_) * (i + 1))]);
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

      const LossValues l = gradient_->compute(mb, stats.epsilon, stats.beta, hp.value_loss_coef);
      if (!std::isfinite(l.total)) {
        std::ostringstream os;
        os << "behavior " << spec_.name << ", update " << updates_ + 1 << ", step " << step_
           << ": loss is " << l.total << " (policy " << l.policy << ", value " << l.value
           << ", entropy " << l.entropy << ")";
        throw BadNumberError(os.str());
      }
      if (hp.max_grad_norm > 0) optimizer_->clip_grad_norm(hp.max_grad_norm);
      optimizer_->step(stats.learning_rate);
      sum_policy += l.policy;
      sum_value += l.value;
      sum_entropy += l.entropy;
    }
  }
  const double count = std::max<int64_t>(1, batches * hp.num_epoch);
  stats.policy_loss = float(sum_policy / count);
  stats.value_loss = float(sum_value / count);
  stats.entropy = float(sum_entropy / count);
  buffer_.clear();
  ++updates_;
  actor_stale_ = true;
  return stats;
}

EpisodeStats PpoTrainer::take_episode_stats() {
  EpisodeStats out;
  std::swap(out, episode_stats_);
  return out;
}

void PpoTrainer::save(torch::serialize::OutputArchive& a) const {
  torch::serialize::OutputArchive weights, optim;
  net_->save(weights);
  optimizer_->save(optim);
  a.write("weights", weights);
  a.write("optimizer", optim);
  write_string(a, "normalizer", normalizer_.serialize());
  std::ostringstream rng;
  rng << rng_;
  write_string(a, "rng", rng.str());
  write_vector(a, "counters", std::vector<int64_t>{step_, updates_});
  write_vector(a, "buffer.obs", buffer_.obs);
  write_vector(a, "buffer.continuous", buffer_.continuous);
  write_vector(a, "buffer.discrete", buffer_.discrete);
  write_vector(a, "buffer.mask", buffer_.mask);
  write_vector(a, "buffer.log_prob", buffer_.log_prob);
  write_vector(a, "buffer.value", buffer_.value);
  write_vector(a, "buffer.returns", buffer_.returns);
  write_vector(a, "buffer.advantages", buffer_.advantages);
  write_vector(a, "episodes.returns", episode_stats_.returns);
  write_vector(a, "episodes.lengths", episode_stats_.lengths);
}

void PpoTrainer::load_weights(torch::serialize::InputArchive& a) {
  torch::serialize::InputArchive weights;
  a.read("weights", weights);
  net_->load(weights);
  optimizer_->relink();  // loading replaced the parameters' storage
  normalizer_ = RunningNormalizer::deserialize(read_string(a, "normalizer"));
  if (normalizer_.size() != obs_size_)
    throw std::runtime_error("checkpoint normalizer of behavior " + spec_.name + " has size " +
                             std::to_string(normalizer_.size()) + ", expected " +
                             std::to_string(obs_size_));
  actor_stale_ = true;
}

void PpoTrainer::load(torch::serialize::InputArchive& a) {
  load_weights(a);
  torch::serialize::InputArchive optim;
  a.read("optimizer", optim);
  optimizer_->load(optim);
  std::istringstream rng(read_string(a, "rng"));
  rng >> rng_;
  auto counters = read_vector<int64_t>(a, "counters");
  step_ = counters.at(0);
  updates_ = counters.at(1);
  buffer_.obs = read_vector<float>(a, "buffer.obs");
  buffer_.continuous = read_vector<float>(a, "buffer.continuous");
  buffer_.discrete = read_vector<int64_t>(a, "buffer.discrete");
  buffer_.mask = read_vector<float>(a, "buffer.mask");
  buffer_.log_prob = read_vector<float>(a, "buffer.log_prob");
  buffer_.value = read_vector<float>(a, "buffer.value");
  buffer_.returns = read_vector<float>(a, "buffer.returns");
  buffer_.advantages = read_vector<float>(a, "buffer.advantages");
  episode_stats_.returns = read_vector<float>(a, "episodes.returns");
  episode_stats_.lengths = read_vector<float>(a, "episodes.lengths");
}

}  // namespace rlt
