#include "rl/trainer/on_policy_trainer.h"

#include <cmath>
#include <cstring>
#include <numeric>
#include <sstream>

#include "rl/core/action_distribution.h"
#include "rl/core/archive_io.h"
#include "rl/core/bad_numbers.h"
#include "rl/distributed/data_parallel.h"

namespace rlt {

namespace {
int total_obs_size(const BehaviorSpec& spec) {
  int n = 0;
  for (const auto& o : spec.observations) n += o.size();
  return n;
}
// [total_obs_size] 1 for the columns of grid observations: normalization leaves them as they are
// (unless network_settings.normalize_grids), as ML-Agents normalizes vector observations only
// (its grids go to a CNN unnormalized). Sparse 0-1 cells that are mostly 0 would otherwise become
// rare spikes of up to kClip.
std::vector<uint8_t> grid_columns(const BehaviorSpec& spec) {
  std::vector<uint8_t> out;
  for (const auto& o : spec.observations)
    out.insert(out.end(), o.size(), o.kind == ObservationKind::kGrid ? 1 : 0);
  return out;
}
}  // namespace

OnPolicyTrainer::OnPolicyTrainer(const BehaviorSpec& spec, const BehaviorConfig& config, int rows,
                                 uint64_t seed, const std::string& env_name, bool with_critic)
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
  shape.with_critic = with_critic;
  net_ = PolicyNetwork(shape);
  if (!config.network_settings.normalize_grids) normalizer_.set_passthrough(grid_columns(spec));

  pending_.assign(rows, 0);
  rewards_.resize(rows);
  episode_return_.assign(rows, 0.0);
  episode_group_return_.assign(rows, 0.0);
  episode_length_.assign(rows, 0);
  whole_episode_.assign(rows, 0);
  buffer_.obs_size = obs_size_;
  buffer_.continuous_size = spec.action.continuous_size;
  buffer_.num_branches = spec.action.num_branches();
  buffer_.mask_size = spec.action.mask_size();
  trajectories_.assign(rows, buffer_);
}

void OnPolicyTrainer::create_optimizer() {
  auto params = net_->parameters();
  for (auto& p : extra_parameters()) params.push_back(p);
  optimizer_ = std::make_unique<FlatAdam>(params);
}

std::string OnPolicyTrainer::where(const BehaviorBuffers& buf, int row) const {
  std::ostringstream os;
  os << "environment " << env_name_ << ", instance " << row / spec_.agent_slots << ", behavior "
     << spec_.name << ", agent " << buf.agent_id[row] << ", step " << step_;
  return os.str();
}

void OnPolicyTrainer::gather_obs(const BehaviorBuffers& buf, const std::vector<int>& rows,
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

void OnPolicyTrainer::refresh_actor() {
  actor_.copy_from(*net_, normalizer());
  actor_stale_ = false;
}

FastActor OnPolicyTrainer::fast_actor() const {
  FastActor a;
  a.copy_from(*net_, normalizer());
  return a;
}

void OnPolicyTrainer::act(BehaviorBuffers& buf, const std::vector<uint8_t>* learner_rows) {
  if (actor_stale_) refresh_actor();
  act_rows_.clear();
  for (int r = 0; r < rows_; ++r)
    if (needs_action(buf.step_type[r]) && (!learner_rows || (*learner_rows)[r])) act_rows_.push_back(r);
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
      episode_group_return_[r] = 0.0;
      episode_length_[r] = 0;
      whole_episode_[r] = 1;
    }
    t.obs.insert(t.obs.end(), act_obs_.data() + i * obs_size_, act_obs_.data() + (i + 1) * obs_size_);
    for (int j = 0; j < c; ++j) t.continuous.push_back(act_out_.continuous(i, j));
    for (int j = 0; j < k; ++j) t.discrete.push_back(act_out_.discrete(i, j));
    for (int j = 0; j < m; ++j) t.mask.push_back(masks[i * m + j]);
    t.log_prob.push_back(act_out_.log_prob[i]);
    t.value.push_back(act_out_.value[i]);
    pending_[r] = 1;
  }
  on_acted(buf, act_rows_);
  step_ += int64_t(act_rows_.size());
}

float OnPolicyTrainer::step_reward(const BehaviorBuffers& buf, int row) const {
  return (buf.reward[row] + buf.group_reward[row]) * config_.extrinsic.strength;
}

void OnPolicyTrainer::observe(const BehaviorBuffers& buf) {
  std::vector<int> terminated, bootstrapped;
  for (int r = 0; r < rows_; ++r) {
    if (!pending_[r]) continue;
    pending_[r] = 0;
    const StepType st = buf.step_type[r];
    const float raw = buf.reward[r] + buf.group_reward[r];
    if (!std::isfinite(raw)) require_finite(&raw, 1, where(buf, r) + ": reward");
    rewards_[r].push_back(step_reward(buf, r));
    episode_return_[r] += buf.reward[r];
    episode_group_return_[r] += buf.group_reward[r];
    episode_length_[r] += 1;
    if (st == StepType::kLast) {
      // an episode joined midway (VectorEnv::stagger, after a checkpoint boundary) is learned
      // from but not counted in the returns
      if (whole_episode_[r]) {
        episode_stats_.returns.push_back(float(episode_return_[r]));
        episode_stats_.group_returns.push_back(float(episode_group_return_[r]));
        episode_stats_.lengths.push_back(float(episode_length_[r]));
      }
      whole_episode_[r] = 0;
      (buf.terminated[r] ? terminated : bootstrapped).push_back(r);
    } else if (int(rewards_[r].size()) >= config_.time_horizon) {
      bootstrapped.push_back(r);
    }
  }
  if (terminated.empty() && bootstrapped.empty()) return;
  if (actor_stale_) refresh_actor();
  end_trajectories(buf, terminated, bootstrapped);
}

void OnPolicyTrainer::interrupt_all(const BehaviorBuffers& buf) {
  std::fill(whole_episode_.begin(), whole_episode_.end(), 0);
  std::vector<int> rows;
  for (int r = 0; r < rows_; ++r)
    if (!rewards_[r].empty()) rows.push_back(r);
  for (int r : rows) {
    // an unanswered decision (acted, env not stepped) is dropped
    auto& t = trajectories_[r];
    const int64_t keep = int64_t(rewards_[r].size());
    t.truncate(keep);
    pending_[r] = 0;
  }
  if (rows.empty()) return;
  if (actor_stale_) refresh_actor();
  end_trajectories(buf, {}, rows);
}

int64_t OnPolicyTrainer::open_steps() const {
  int64_t n = 0;
  for (const auto& r : rewards_) n += int64_t(r.size());
  return n;
}

float OnPolicyTrainer::decayed(float initial, float minimum, Schedule schedule) const {
  if (schedule == Schedule::kConstant) return initial;
  const double frac = std::min(1.0, double(step_) / double(config_.max_steps));
  return float(std::max(double(minimum), initial - (initial - minimum) * frac));
}

void OnPolicyTrainer::fill_schedules(UpdateStats& stats) const {
  const auto& hp = config_.hyperparameters;
  stats.learning_rate = decayed(hp.learning_rate, 1e-10f, hp.learning_rate_schedule);
  stats.epsilon = decayed(hp.epsilon, 0.1f, hp.epsilon_schedule.value_or(hp.learning_rate_schedule));
  stats.beta = decayed(hp.beta, 1e-5f, hp.beta_schedule.value_or(hp.learning_rate_schedule));
  // the branches' own bonus first moves to discrete_beta_end over discrete_beta_steps
  float discrete = hp.discrete_beta.value_or(hp.beta);
  if (hp.discrete_beta_steps > 0 && hp.discrete_beta_end) {
    const double frac = std::min(1.0, double(step_) / double(hp.discrete_beta_steps));
    discrete = float(discrete + (*hp.discrete_beta_end - discrete) * frac);
  }
  stats.discrete_beta =
      decayed(discrete, 1e-5f, hp.beta_schedule.value_or(hp.learning_rate_schedule));
}

double OnPolicyTrainer::actor_macs() const {
  const double d = obs_size_, h = config_.network_settings.hidden_units;
  const int layers = config_.network_settings.num_layers;
  const double heads = spec_.action.continuous_size + spec_.action.mask_size();
  return d * h + (layers - 1) * h * h + h * heads;
}

double OnPolicyTrainer::actor_input_macs() const {
  return double(obs_size_) * config_.network_settings.hidden_units;
}

double OnPolicyTrainer::ppo_critic_macs() const {
  const double d = obs_size_, h = config_.network_settings.hidden_units;
  const int layers = config_.network_settings.num_layers;
  if (config_.hyperparameters.shared_critic) return h;
  return d * h + (layers - 1) * h * h + h;
}

torch::Tensor OnPolicyTrainer::normalize(const torch::Tensor& obs) const {
  if (!config_.network_settings.normalize) return obs;
  auto mean = torch::tensor(normalizer_.mean_float());  // [D]
  auto inv = torch::tensor(normalizer_.inverse_std());  // [D]
  return ((obs - mean) * inv).clamp(-RunningNormalizer::kClip, RunningNormalizer::kClip);
}

std::vector<int64_t> OnPolicyTrainer::permutation(int64_t n) {
  // Fisher-Yates with our own engine
  std::vector<int64_t> perm(n);
  std::iota(perm.begin(), perm.end(), 0);
  for (int64_t i = n - 1; i > 0; --i) std::swap(perm[i], perm[int64_t(uniform01(rng_) * (i + 1))]);
  return perm;
}

EpisodeStats OnPolicyTrainer::take_episode_stats() {
  EpisodeStats out;
  std::swap(out, episode_stats_);
  return out;
}

void OnPolicyTrainer::save(torch::serialize::OutputArchive& a) const {
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
  buffer_.save(a, "buffer.");
  write_vector(a, "episodes.returns", episode_stats_.returns);
  write_vector(a, "episodes.lengths", episode_stats_.lengths);
  write_vector(a, "episodes.group_returns", episode_stats_.group_returns);
  save_extra(a);
}

void OnPolicyTrainer::load_weights(torch::serialize::InputArchive& a) {
  torch::serialize::InputArchive weights;
  a.read("weights", weights);
  net_->load(weights);
  load_extra(a);
  optimizer_->relink();  // loading replaced the parameters' storage
  normalizer_ = RunningNormalizer::deserialize(read_string(a, "normalizer"));
  if (normalizer_.size() != obs_size_)
    throw std::runtime_error("checkpoint normalizer of behavior " + spec_.name + " has size " +
                             std::to_string(normalizer_.size()) + ", expected " +
                             std::to_string(obs_size_));
  // a checkpoint written since grids pass through has them at exactly mean 0, variance 1; one
  // from before keeps normalizing its grids, as its network was trained
  const std::vector<uint8_t> grids = grid_columns(spec_);
  bool passed_through = true;
  for (int i = 0; i < obs_size_; ++i)
    passed_through = passed_through && (!grids[i] || (normalizer_.mean()[i] == 0.0 &&
                                                      normalizer_.variance()[i] == 1.0));
  if (passed_through && !config_.network_settings.normalize_grids)
    normalizer_.set_passthrough(grids);
  actor_stale_ = true;
}

void OnPolicyTrainer::load(torch::serialize::InputArchive& a) {
  load_weights(a);
  torch::serialize::InputArchive optim;
  a.read("optimizer", optim);
  optimizer_->load(optim);
  std::istringstream rng(read_string(a, "rng"));
  rng >> rng_;
  auto counters = read_vector<int64_t>(a, "counters");
  step_ = counters.at(0);
  updates_ = counters.at(1);
  buffer_.load(a, "buffer.");
  episode_stats_.returns = read_vector<float>(a, "episodes.returns");
  episode_stats_.lengths = read_vector<float>(a, "episodes.lengths");
  episode_stats_.group_returns = read_vector<float>(a, "episodes.group_returns");
}

void OnPolicyTrainer::set_communicator(Communicator* comm) {
  comm_ = comm && comm->world_size() > 1 ? comm : nullptr;
  pending_normalizer_ = RunningNormalizer(obs_size_);
  if (!comm_) return;
  const auto& hp = config_.hyperparameters;
  const int w = comm_->world_size();
  if (hp.batch_size % w != 0 || hp.buffer_size % w != 0)
    throw std::invalid_argument("behavior " + spec_.name + ": batch_size " +
                                std::to_string(hp.batch_size) + " and buffer_size " +
                                std::to_string(hp.buffer_size) + " must divide among " +
                                std::to_string(w) + " ranks");
}

void OnPolicyTrainer::broadcast_parameters(int root) {
  if (!comm_) return;
  torch::Tensor p = optimizer_->flat_parameters();  // [P], shares the storage
  comm_->broadcast(p, root, "sharing the initial parameters");
  actor_stale_ = true;
}

void OnPolicyTrainer::fold_observations(const float* obs, int64_t rows) {
  if (!config_.network_settings.normalize) return;
  if (comm_) {
    pending_normalizer_.update(obs, rows);
  } else {
    normalizer_.update(obs, rows);
    actor_stale_ = true;
  }
}

void OnPolicyTrainer::sync_normalizer() {
  if (!comm_ || !config_.network_settings.normalize) return;
  merge_normalizers(*comm_, normalizer_, pending_normalizer_);
  actor_stale_ = true;
}

int64_t OnPolicyTrainer::local_batch_size() const {
  return config_.hyperparameters.batch_size / (comm_ ? comm_->world_size() : 1);
}

int64_t OnPolicyTrainer::agreed_batches(int64_t n) {
  const int64_t mine = n / local_batch_size();
  return comm_ ? global_min(*comm_, mine, "agreeing on the minibatches") : mine;
}

torch::Tensor OnPolicyTrainer::normalize_advantages(const torch::Tensor& adv) {
  if (!comm_) return (adv - adv.mean()) / (adv.std() + 1e-10f);
  const auto [mean, std] = global_mean_std(*comm_, adv);
  return (adv - float(mean)) / (float(std) + 1e-10f);
}

void OnPolicyTrainer::reduce_gradients() {
  if (comm_) average_gradients(*comm_, optimizer_->flat_gradients());
}

}  // namespace rlt
