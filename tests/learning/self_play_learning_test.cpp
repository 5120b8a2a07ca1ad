// Self-play on the symmetric Duel game: the learner's ELO rises and, with swaps, the two teams end
// balanced; the negative control (swap_steps and team_change beyond max_steps, so the opponent is
// never replaced by a competent snapshot) is lopsided: the learning team wins nearly every game.
// The control mirrors ML-Agents' test_simple_ghost_fails. Label: learning.
#include <gtest/gtest.h>

#include <deque>
#include <numeric>
#include <sstream>

#include "env/register_builtin_envs.h"
#include "rl/config/config_parser.h"
#include "rl/trainer/training_run.h"

namespace rlt {
namespace {

struct DuelResult {
  double elo;              // learner's ELO at the end
  double win_team0;        // mean over the last 300 games (1 team 0 won, 0 team 1, 0.5 draw)
  double decisive;         // fraction of those games that were not draws
};

DuelResult train_duel(bool never_swap) {
  register_builtin_envs();
  RunConfig config = load_run_config("configs/duel_selfplay.yaml");
  auto& sp = *config.behaviors.at("Duelist").self_play;
  if (never_swap) sp.swap_steps = sp.team_change = 1000000000;
  TrainOptions opt;
  opt.write_results = false;
  opt.progress = false;
  std::ostringstream log;
  opt.log = &log;
  std::deque<std::pair<double, double>> last;  // (win_team0, draw)
  opt.on_env_episode = [&](const EpisodeMetrics& m) {
    last.emplace_back(m.at("win_team0"), m.at("draw"));
    if (last.size() > 300) last.pop_front();
  };
  TrainingRun run(config, opt);
  run.train();
  DuelResult r;
  r.elo = run.self_play().elo(0);
  double wins = 0, draws = 0;
  for (auto& [w, d] : last) {
    wins += w;
    draws += d;
  }
  r.win_team0 = wins / last.size();
  r.decisive = 1 - draws / last.size();
  std::cout << (never_swap ? "never swapping" : "swapping") << ": ELO " << r.elo
            << ", win_team0 " << r.win_team0 << ", decisive games " << r.decisive << "\n";
  return r;
}

TEST(SelfPlayLearning, EloRisesAndTeamsEndBalanced) {
  const DuelResult r = train_duel(false);
  EXPECT_GT(r.elo, 1200 + 300);
  EXPECT_NEAR(r.win_team0, 0.5, 0.2);
}

TEST(SelfPlayLearning, NeverSwappingIsLopsided) {
  const DuelResult r = train_duel(true);
  EXPECT_GT(r.win_team0, 0.9);  // team 0 learns for the whole run against its initial policy
  EXPECT_GT(r.decisive, 0.8);
}

}  // namespace
}  // namespace rlt
