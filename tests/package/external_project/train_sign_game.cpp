// A user's own environment trained with the installed toolkit: each step shows a sign (+1 or -1)
// and pays 1 for choosing action 1 on +1 and action 0 on -1; episodes last 10 steps. Random play
// earns 5 per episode. Exits 0 when PPO earns more than 9 over the last 100 episodes.
#include <rl/config/config_parser.h>
#include <rl/env_api/env.h>
#include <rl/env_api/env_registry.h>
#include <rl/trainer/training_run.h>

#include <iostream>
#include <memory>
#include <numeric>
#include <random>
#include <vector>

namespace {

class SignGame : public rlt::Env {
 public:
  SignGame() {
    rlt::BehaviorSpec b;
    b.name = "Guesser";
    b.observations.push_back({"sign", {1}, rlt::ObservationKind::kVector, -1.f, 1.f});
    b.action.discrete_branches = {2};
    spec_.name = "SignGame";
    spec_.behaviors.push_back(b);
    spec_.max_episode_steps = 10;
  }
  const rlt::EnvSpec& spec() const override { return spec_; }
  void seed(uint64_t s) override { engine_.seed(s); }
  void reset(rlt::StepView& out) override {
    t_ = 0;
    out[0].step_type(0) = rlt::StepType::kFirst;
    out[0].agent_id(0) = 0;
    show(out);
  }
  void step(rlt::StepView& io) override {
    ++t_;
    const int choice = io[0].discrete_action(0)[0];
    io[0].reward(0) = (choice == 1) == (sign_ > 0) ? 1.f : 0.f;
    io[0].step_type(0) = t_ >= spec_.max_episode_steps ? rlt::StepType::kLast : rlt::StepType::kMid;
    show(io);
  }

 private:
  void show(rlt::StepView& v) {
    sign_ = (engine_() & 1) ? 1.f : -1.f;
    v[0].observation(0)[0] = sign_;
  }
  rlt::EnvSpec spec_;
  std::mt19937_64 engine_;
  float sign_ = 1.f;
  int t_ = 0;
};

}  // namespace

int main() {
  rlt::EnvRegistry::instance().add(
      "SignGame", [](const rlt::Parameters&) { return std::unique_ptr<rlt::Env>(new SignGame()); });
  const rlt::RunConfig config = rlt::load_run_config_from_string(R"(
behaviors:
  Guesser:
    trainer_type: ppo
    hyperparameters: {batch_size: 64, buffer_size: 512, learning_rate: 0.003}
    network_settings: {hidden_units: 32, num_layers: 1}
    max_steps: 8000
    summary_freq: 4000
env_settings: {env_id: SignGame, num_envs: 4, seed: 1}
)",
                                                                 "sign_game.yaml");
  rlt::TrainOptions options;
  options.write_results = false;
  options.progress = false;
  options.threads = 1;
  std::vector<float> returns;
  options.on_episode = [&](int, int64_t, float r) { returns.push_back(r); };
  rlt::TrainingRun run(config, options);
  run.train();
  const size_t n = std::min<size_t>(100, returns.size());
  const double mean = n ? std::accumulate(returns.end() - n, returns.end(), 0.0) / n : 0.0;
  std::cout << "mean return over the last " << n << " episodes: " << mean << std::endl;
  return mean > 9.0 ? 0 : 1;
}
