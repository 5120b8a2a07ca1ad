#include "rl/trainer/training_run.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <set>
#include <sstream>
#include <thread>

#include "rl/config/config_parser.h"
#include "rl/core/allocator_tuning.h"
#include "rl/core/archive_io.h"
#include "rl/core/atomic_file.h"
#include "rl/core/compute_threads.h"
#include "rl/core/csv_line.h"
#include "rl/core/json.h"
#include "rl/core/machine_info.h"
#include "rl/core/policy_export.h"
#include "rl/core/sample_stats.h"
#include "rl/curriculum/environment_parameter_manager.h"
#include "rl/distributed/data_parallel.h"
#include "rl/env_api/derived_seed.h"
#include "rl/trainer/trainer_factory.h"

namespace fs = std::filesystem;

namespace rlt {

namespace {

const char* kMetricsHeader =
    "step,elapsed_s,episodes,mean_return,std_return,mean_length,policy_loss,value_loss,"
    "baseline_loss,entropy,learning_rate,epsilon,beta,elo,approx_kl,clip_fraction\n";

// keeps the rows of a metrics file whose step is <= `step` (after a resume). A last row without
// its newline is the start of a write that was cut off (a kill, a full disk) and goes too: its
// first field may be a prefix of the step it was meant to hold. With `header` (the columns the
// run writes), a file written before columns were added, wherever they fall, gets the new header
// and its kept rows their fields moved under it, empty for the new columns; a header with a
// column the run does not write is an error and the file is left as it was.
void truncate_metrics(const std::string& path, int64_t step, const std::string& header = "") {
  std::ifstream in(path, std::ios::binary);
  if (!in) return;
  std::string contents((std::istreambuf_iterator<char>(in)), {});
  if (!contents.empty() && contents.back() != '\n') contents.erase(contents.rfind('\n') + 1);
  std::istringstream lines(contents);
  std::string line, kept;
  std::vector<int> place;  // each old column's index in the new header (empty: the same header)
  int new_columns = 0;
  for (int64_t number = 1; std::getline(lines, line); ++number) {
    if (number == 1) {  // the header
      const std::string wanted = header.empty() ? line : header.substr(0, header.find('\n'));
      if (line != wanted) {
        const std::vector<std::string> old = split_csv_line(line), now = split_csv_line(wanted);
        new_columns = int(now.size());
        for (const std::string& name : old) {
          const auto at = std::find(now.begin(), now.end(), name);
          const bool twice = std::count(old.begin(), old.end(), name) > 1;
          if (at == now.end() || twice)
            throw std::runtime_error(path + ":1: the header is '" + line + "', expected '" + wanted +
                                     "' (column '" + name + "' " +
                                     (twice ? "appears twice" : "is not written any more") +
                                     "; the run was not resumed; the file was left as it was)");
          place.push_back(int(at - now.begin()));
        }
      }
      kept += wanted + "\n";
      continue;
    }
    const std::string first = line.substr(0, line.find(','));
    char* end = nullptr;
    const long long row_step = std::strtoll(first.c_str(), &end, 10);
    if (first.empty() || *end != '\0')
      throw std::runtime_error(path + ":" + std::to_string(number) + ": expected a step, got '" +
                               first + "' (the run was not resumed; the file was left as it was)");
    if (row_step > step) continue;
    if (place.empty()) {
      kept += line + "\n";
      continue;
    }
    const std::vector<std::string> fields = split_csv_line(line);
    if (fields.size() != place.size())
      throw std::runtime_error(path + ":" + std::to_string(number) + ": " +
                               std::to_string(fields.size()) + " fields under a header of " +
                               std::to_string(place.size()) +
                               " (the run was not resumed; the file was left as it was)");
    std::vector<std::string> moved(new_columns);
    for (size_t i = 0; i < fields.size(); ++i) moved[place[i]] = fields[i];
    for (int i = 0; i < new_columns; ++i) kept += (i ? "," : "") + moved[i];
    kept += "\n";
  }
  write_file_atomically(path, kept);
}

// sums and counts of named metrics (metric: sum, count) as a sub-archive: the names one per line,
// the sums, and the counts after `leading`, a count of the caller's
using MetricSums = std::map<std::string, std::pair<double, int>>;

void write_metric_sums(torch::serialize::OutputArchive& archive, const std::string& key,
                       const MetricSums& metrics, int64_t leading) {
  torch::serialize::OutputArchive a;
  std::string names;
  std::vector<double> sums;
  std::vector<int64_t> counts = {leading};
  for (const auto& [name, sum_count] : metrics) {
    names += name + "\n";
    sums.push_back(sum_count.first);
    counts.push_back(sum_count.second);
  }
  write_string(a, "names", names);
  write_vector(a, "sums", sums);
  write_vector(a, "counts", counts);
  archive.write(key, a);
}

// false (and `metrics` and `leading` untouched) when the archive has no `key`: older checkpoints
bool read_metric_sums(torch::serialize::InputArchive& archive, const std::string& key,
                      MetricSums& metrics, int64_t& leading) {
  torch::serialize::InputArchive a;
  if (!archive.try_read(key, a)) return false;
  std::istringstream names(read_string(a, "names"));
  const auto sums = read_vector<double>(a, "sums");
  const auto counts = read_vector<int64_t>(a, "counts");
  leading = counts.at(0);
  metrics.clear();
  std::string name;
  for (size_t i = 0; std::getline(names, name); ++i)
    metrics[name] = {sums.at(i), int(counts.at(i + 1))};
  return true;
}

}  // namespace

TrainingRun::TrainingRun(RunConfig config, TrainOptions options)
    : config_(std::move(config)), options_(std::move(options)) {
  log_ = options_.log ? options_.log : &std::cout;
  if (rank() != 0) {  // summaries and progress are rank 0's
    static std::ostream discard(nullptr);
    log_ = &discard;
    options_.progress = false;
  }
  // command-line overrides
  auto& cs = config_.checkpoint_settings;
  auto& es = config_.env_settings;
  if (!options_.run_id.empty()) cs.run_id = options_.run_id;
  if (!options_.results_dir.empty()) cs.results_dir = options_.results_dir;
  if (options_.resume) cs.resume = true;
  if (options_.force) cs.force = true;
  if (!options_.initialize_from.empty()) cs.initialize_from = options_.initialize_from;
  if (cs.resume && cs.force) throw std::invalid_argument("--resume and --force exclude each other");
  if (options_.num_envs > 0) es.num_envs = options_.num_envs;
  if (options_.seed >= 0) es.seed = options_.seed;
  if (cs.resume) keep_the_runs_seed();
  if (options_.threads > 0) es.num_threads = options_.threads;
  for (const auto& [name, value] : options_.params) {
    bool controlled = config_.environment_parameters.count(name) > 0;
    for (const auto& [other, parameter] : config_.environment_parameters)
      controlled = controlled || parameter.other_parameters().count(name) > 0;
    if (controlled)
      throw std::invalid_argument("--param " + name + ": " + config_.source_file +
                                  " sets it in environment_parameters");
    for (const auto& [behavior, b] : config_.behaviors)
      if (b.self_play && b.self_play->turn_parameters.count(name))
        throw std::invalid_argument("--param " + name + ": " + config_.source_file +
                                    " sets it in behaviors." + behavior +
                                    ".self_play.turn_parameters");
    es.params[name] = value;
  }
  if (options_.max_steps > 0) {
    for (auto& [name, b] : config_.behaviors) b.max_steps = options_.max_steps;
    if (config_.default_settings) config_.default_settings->max_steps = options_.max_steps;
  }
  for (const auto& [name, steps] : options_.behavior_max_steps)
    if (steps < 1)
      throw std::invalid_argument("--max-steps " + name + "=" + std::to_string(steps) +
                                  ": must be at least 1");
  seed_ = es.seed >= 0 ? uint64_t(es.seed) : 0;
  rank_seed_ = derived_seed(seed_, uint64_t(rank()));
  int threads = es.num_threads > 0 ? es.num_threads : int(std::max(1u, std::thread::hardware_concurrency()));
  threads_ = threads;
  set_compute_threads(1);
  tune_allocator_for_training();

  // the environment and one trainer per behavior (all validation before anything is written)
  env_ = std::make_unique<VectorEnv>(es.env_id, es.num_envs, rank_seed_, es.params,
                                     std::min(threads, es.num_envs));
  parameters_ = EnvironmentParameterManager(config_.environment_parameters);
  // data-parallel: rank 0's episodes move the staircases and the others take its values
  parameters_.set_staircases_follow_only(rank() != 0);
  parameter_rng_.seed(rank_seed_ * 6151 + 11);
  // names are checked by set_parameters, values by the envs at reset: each behavior's turn
  // parameters first, then the first lessons, before anything is written
  for (const auto& [name, b] : config_.behaviors) {
    if (!b.self_play || b.self_play->turn_parameters.empty()) continue;
    Parameters turn = parameters_.sample(uint64_t(0));
    for (const auto& [key, value] : b.self_play->turn_parameters) turn[key] = value;
    try {
      env_->set_parameters(turn);
      env_->reset();
    } catch (const std::exception& e) {
      throw std::invalid_argument(config_.source_file + ": behaviors." + name +
                                  ".self_play.turn_parameters: " + e.what());
    }
    for (const auto& [key, value] : b.self_play->turn_parameters) {
      auto given = es.params.find(key);
      turn_fallback_[key] =
          given != es.params.end() ? given->second : env_->spec().default_parameters.at(key);
    }
  }
  check_every_lesson();
  env_->set_parameters(turn_fallback_);
  env_->set_parameters(parameters_.sample(parameter_rng_));
  env_->reset();
  episode_epoch_.assign(env_->num_envs(), 0);
  episode_turn_.assign(env_->num_envs(), 0);
  try {
    parameters_.check_metric_names(env_->episode_metric_names());
    std::vector<std::string> strategy_names;
    for (const StrategySpec& s : env_->spec().strategies) strategy_names.push_back(s.name);
    parameters_.check_strategy_names(strategy_names);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(config_.source_file + ": " + e.what());
  }
  check_until_emerged();
  const EnvSpec& spec = env_->spec();
  std::string known_behaviors;
  for (const auto& bs : spec.behaviors)
    known_behaviors += (known_behaviors.empty() ? "" : ", ") + bs.name;
  for (const auto& [name, b] : config_.behaviors)
    if (spec.behavior_index(name) < 0)
      throw std::invalid_argument(config_.source_file + ": behaviors." + name + ": environment " +
                                  spec.name + " has no behavior '" + name + "' (it has: " +
                                  known_behaviors + ")");
  for (const auto& [name, steps] : options_.behavior_max_steps)
    if (spec.behavior_index(name) < 0)
      throw std::invalid_argument("--max-steps " + name + "=" + std::to_string(steps) +
                                  ": environment " + spec.name + " has no behavior '" + name +
                                  "' (it has: " + known_behaviors + ")");
  for (int b = 0; b < int(spec.behaviors.size()); ++b) {
    const BehaviorSpec& bs = spec.behaviors[b];
    BehaviorConfig bc = behavior_config(config_, bs.name);
    if (const int64_t steps = command_line_max_steps(bs.name)) bc.max_steps = steps;
    config_.behaviors[bs.name] = bc;
    torch::manual_seed(seed_ * 7919 + b);
    trainers_.push_back(
        make_trainer(bs, bc, env_->buffers(b).rows, rank_seed_ * 1000003 + 17 * b + 1, spec.name));
    trainers_.back()->set_communicator(options_.communicator);
  }
  apply_step_budgets();
  reset_self_play();
  summary_returns_.resize(trainers_.size());
  summary_group_returns_.resize(trainers_.size());
  summary_metrics_.resize(trainers_.size());
  summary_lengths_.resize(trainers_.size());
  summary_updates_.resize(trainers_.size());
  last_summary_.resize(trainers_.size());
  tensorboard_.resize(trainers_.size());
  update_window_.resize(trainers_.size());
  strategies_ = StrategyTracker(spec.strategies);
  for (const auto& s : spec.strategies)
    if (spec.behavior_index(s.behavior) < 0)
      throw std::invalid_argument("environment " + spec.name + ": strategy " + s.name +
                                  " is dated in steps of unknown behavior '" + s.behavior + "'");

  if (!options_.write_results) {
    for (auto& t : trainers_) t->broadcast_parameters(0);
    return;
  }
  std::string init_checkpoint;
  if (!cs.initialize_from.empty()) {
    RunFolder source(cs.results_dir, cs.initialize_from);
    auto st = source.read_status();
    if (st.checkpoints.empty())
      throw std::runtime_error(source.path() + " has no checkpoint to initialize from");
    init_checkpoint = source.file(st.checkpoints.back().file);
  }
  if (rank() != 0) {
    // the other ranks read what rank 0 wrote (the same folder, or a copy) and write nothing
    RunFolder shared(cs.results_dir, cs.run_id);
    if (cs.resume) {
      const TrainingStatus st = shared.read_status();
      if (!st.checkpoints.empty()) load_checkpoint(shared.file(st.checkpoints.back().file), false);
    } else if (!init_checkpoint.empty()) {
      load_checkpoint(init_checkpoint, true);
      reset_self_play();  // the opponent pool starts from the loaded weights
    }
    for (auto& t : trainers_) t->broadcast_parameters(0);
    return;
  }
  folder_ = std::make_unique<RunFolder>(cs.results_dir, cs.run_id);
  if (cs.resume) {
    if (!folder_->exists())
      throw std::runtime_error("cannot resume: run folder " + folder_->path() + " does not exist");
    status_ = folder_->read_status();
    if (!status_.checkpoints.empty()) {
      const auto& last = status_.checkpoints.back();
      load_checkpoint(folder_->file(last.file), false);
      for (auto& t : trainers_)
        truncate_metrics(folder_->metrics_path(t->behavior()), t->step(), kMetricsHeader);
      truncate_metrics(folder_->episode_metrics_path(), total_steps(), episode_metrics_header());
      truncate_metrics(folder_->lesson_changes_path(), total_steps(), lesson_changes_header());
    }
    status_.finished = false;
  } else {
    folder_->create(cs.force);
    status_ = TrainingStatus{};
    status_.run_id = cs.run_id;
    if (!init_checkpoint.empty()) {
      load_checkpoint(init_checkpoint, true);
      reset_self_play();  // the opponent pool starts from the loaded weights
    }
    for (auto& t : trainers_) write_file_atomically(folder_->metrics_path(t->behavior()), kMetricsHeader);
    status_.strategies = strategies_.emergences();
  }
  begin_session(cs.resume);
  write_file_atomically(folder_->config_path(), run_config_to_yaml(config_));
  folder_->write_status(status_);
  for (auto& t : trainers_) t->broadcast_parameters(0);
}

void TrainingRun::check_every_lesson() {
  for (const auto& [name, parameter] : config_.environment_parameters) {
    for (int lesson = 0; lesson < int(parameter.curriculum.size()); ++lesson) {
      EnvironmentParameterManager at_lesson = parameters_;
      at_lesson.follow({{name, lesson}});
      try {
        env_->set_parameters(turn_fallback_);
        // one draw of the lesson's samplers, from an engine of its own (the run's stays untouched)
        env_->set_parameters(at_lesson.sample(uint64_t(lesson)));
        env_->reset();
        // a staircase's far end too: its start is the lesson's own value, tried above
        if (const auto& staircase = parameter.curriculum[lesson].staircase) {
          at_lesson.follow({}, {{name, staircase->end}});
          env_->set_parameters(at_lesson.sample(uint64_t(lesson)));
          env_->reset();
        }
      } catch (const std::exception& e) {
        throw std::invalid_argument(config_.source_file + ": environment_parameters." + name +
                                    ", lesson '" + parameter.curriculum[lesson].name + "': " +
                                    e.what());
      }
    }
  }
}

void TrainingRun::keep_the_runs_seed() {
  // the boundaries reseed the env instances from the seed, so a resume under another seed plays
  // other episodes from its first boundary on: without --seed, the run's own seed (its folder's
  // configuration.yaml) holds, whatever the config file given now says
  auto& es = config_.env_settings;
  const auto& cs = config_.checkpoint_settings;
  const RunFolder folder(cs.results_dir, cs.run_id);
  std::error_code error;
  if (!std::filesystem::exists(folder.config_path(), error)) return;  // resuming fails later
  int64_t runs_seed = -1;
  try {
    runs_seed = load_run_config(folder.config_path()).env_settings.seed;
  } catch (const std::exception& e) {
    throw std::runtime_error("cannot resume: the run's " + folder.config_path() + ": " + e.what());
  }
  if (options_.seed < 0) {
    es.seed = runs_seed;
  } else if (options_.seed != runs_seed) {
    *log_ << "Note: resuming with --seed " << options_.seed << " where the run began with seed "
          << runs_seed << ": from the first boundary on its episodes are not the run's own."
          << std::endl;
  }
}

void TrainingRun::begin_session(bool resumed) {
  RunSession session;
  const std::time_t now = std::time(nullptr);
  std::tm utc{};
  gmtime_r(&now, &utc);
  char started[32];
  std::strftime(started, sizeof started, "%Y-%m-%dT%H:%M:%SZ", &utc);
  session.started = started;
  for (const auto& t : trainers_) session.steps[t->behavior()] = t->step();
  session.machine = current_machine();
  if (resumed && !status_.sessions.empty()) {
    const std::string changed = machine_difference(status_.sessions.back().machine, session.machine);
    if (!changed.empty())
      *log_ << "Note: resuming on another machine or build than the run's last session (" << changed
            << "): from here on the run will not match one that never stopped, since a seed gives "
               "the same trajectory only on one machine and build."
            << std::endl;
  }
  status_.sessions.push_back(session);
}

TrainingRun::~TrainingRun() = default;

double TrainingRun::elapsed() const {
  return elapsed_before_ +
         std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

uint64_t TrainingRun::boundary_seed(int64_t index) const {
  return derived_seed(rank_seed_, uint64_t(index));
}

TrainResult TrainingRun::train(int stop_after_boundaries) {
  start_ = std::chrono::steady_clock::now();
  const int nb = num_trainers();
  next_summary_.assign(nb, 0);
  summarized_step_.assign(nb, 0);
  next_checkpoint_.assign(nb, 0);
  for (int b = 0; b < nb; ++b) {
    const auto& c = trainers_[b]->config();
    next_summary_[b] = (trainers_[b]->step() / c.summary_freq + 1) * c.summary_freq;
    summarized_step_[b] = trainers_[b]->step();
    next_checkpoint_[b] = (trainers_[b]->step() / c.checkpoint_interval + 1) * c.checkpoint_interval;
  }
  synced_step_.assign(nb, 0);
  for (int b = 0; b < nb; ++b) synced_step_[b] = trainers_[b]->step();
  ready_.assign(nb, 0);
  TrainResult result;
  result.trainer_update_seconds.assign(nb, 0.0);
  result.trainer_update_matmul_flops.assign(nb, 0.0);
  int64_t start_steps = 0;
  for (auto& t : trainers_) start_steps += t->step();
  int boundaries = 0;
  auto all_finished = [&] {
    return std::all_of(trainers_.begin(), trainers_.end(), [](auto& t) { return t->finished(); });
  };
  std::vector<BehaviorBuffers*> buffers;
  for (int b = 0; b < nb; ++b) buffers.push_back(&env_->buffers(b));
  sample_all_parameters();
  env_->reseed_and_reset(boundary_seed(boundary_index_));
  env_->stagger(config_.env_settings.stagger_steps);
  using Clock = std::chrono::steady_clock;
  auto seconds_since = [](Clock::time_point t) {
    return std::chrono::duration<double>(Clock::now() - t).count();
  };
  auto done = [&] { return all_finished() || awaited_strategies_emerged(); };
  while (!done()) {
    // act, step, learn
    auto t0 = Clock::now();
    if (self_play_->enabled()) {
      self_play_->select_rows(buffers, learner_rows_);
      for (int b = 0; b < nb; ++b) trainers_[b]->act(env_->buffers(b), &learner_rows_[b]);
      self_play_->act_opponents(buffers, learner_rows_);
    } else {
      for (int b = 0; b < nb; ++b) trainers_[b]->act(env_->buffers(b));
    }
    result.acting_seconds += seconds_since(t0);
    t0 = Clock::now();
    env_->step();
    result.env_seconds += seconds_since(t0);
    result.env_steps += env_->num_envs();
    t0 = Clock::now();
    std::vector<EpisodeStats> episodes(nb);
    for (int b = 0; b < nb; ++b) {
      trainers_[b]->observe(env_->buffers(b));
      auto& ep = episodes[b] = trainers_[b]->take_episode_stats();
      summary_returns_[b].insert(summary_returns_[b].end(), ep.returns.begin(), ep.returns.end());
      summary_group_returns_[b].insert(summary_group_returns_[b].end(), ep.group_returns.begin(),
                                       ep.group_returns.end());
      summary_lengths_[b].insert(summary_lengths_[b].end(), ep.lengths.begin(), ep.lengths.end());
      auto& w = update_window_[b];
      w.returns.insert(w.returns.end(), ep.returns.begin(), ep.returns.end());
      w.lengths.insert(w.lengths.end(), ep.lengths.begin(), ep.lengths.end());
      if (options_.on_episode)
        for (float r : ep.returns) options_.on_episode(b, trainers_[b]->step(), r);
    }
    if (distributed()) sync_ranks();
    if (self_play_->enabled()) self_play_->after_step(buffers, learner_rows_);
    const auto finished = env_->take_finished_episodes();
    for (const auto& f : finished) {
      if (options_.on_env_episode) options_.on_env_episode(f.metrics);
      for (auto& window : summary_metrics_)
        for (const auto& [name, value] : f.metrics) {
          window[name].first += value;
          window[name].second += 1;
        }
    }
    track_episodes(finished);
    update_curriculum(finished, episodes);
    result.trajectory_seconds += seconds_since(t0);
    for (int b = 0; b < nb; ++b) {
      auto& t = *trainers_[b];
      if (!t.finished() && (distributed() ? ready_[b] != 0 : t.update_ready())) {
        t0 = Clock::now();
        const int learner_threads =
            update_threads(t.obs_size(), t.config().network_settings.hidden_units, threads_);
        if (learner_threads > 1) set_blas_threads(learner_threads);
        UpdateStats stats = t.update();
        if (learner_threads > 1) set_blas_threads(1);
        if (distributed()) check_replicas(b);
        const double seconds = seconds_since(t0);
        result.update_seconds += seconds;
        result.update_matmul_flops += stats.matmul_flops;
        result.trainer_update_seconds[b] += seconds;
        result.trainer_update_matmul_flops[b] += stats.matmul_flops;
        log_update(b, stats);
      }
      if (t.step() >= next_summary_[b]) {
        summarize(b);
        summarized_step_[b] = t.step();
        while (next_summary_[b] <= t.step()) next_summary_[b] += t.config().summary_freq;
      }
    }
    show_progress(false);
    // checkpoint boundary when any behavior crossed its interval
    bool due = false;
    for (int b = 0; b < nb; ++b) due |= trainers_[b]->step() >= next_checkpoint_[b];
    if (due && !done()) {
      boundary(false);
      if (stop_after_boundaries > 0 && ++boundaries >= stop_after_boundaries) break;
    }
  }
  if (done()) {
    if (!all_finished()) {
      std::string names;
      for (const std::string& n : options_.until_emerged) names += (names.empty() ? "" : ", ") + n;
      *log_ << "Stopping: " << names << " emerged (--until-emerged)." << std::endl;
    }
    // a last summary of what happened since the previous one
    for (int b = 0; b < nb; ++b)
      if (trainers_[b]->step() > summarized_step_[b]) summarize(b);
    boundary(true);
  }
  show_progress(true);
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  for (auto& t : trainers_) result.agent_steps += t->step();
  result.agent_steps -= start_steps;
  return result;
}

void TrainingRun::sync_ranks() {
  Communicator& comm = *options_.communicator;
  const int nb = num_trainers(), world = comm.world_size();
  const std::map<std::string, int> lessons = parameters_.lessons();  // the same names on every rank
  const std::vector<double> elo = self_play_->elo_state();
  // this rank's slot: per behavior its decisions since the last sync and its buffered experiences;
  // then rank 0's lessons, staircase values and ratings (zeros elsewhere)
  std::vector<double> mine;
  for (int b = 0; b < nb; ++b) {
    mine.push_back(double(trainers_[b]->step() - synced_step_[b]));
    mine.push_back(double(trainers_[b]->buffered()));
  }
  for (const auto& [name, lesson] : lessons) mine.push_back(rank() == 0 ? lesson : 0);
  // the staircases' values, one per curriculum (0 where none)
  const std::map<std::string, double> staircases = parameters_.staircase_values();
  for (const auto& [name, lesson] : lessons) {
    const auto value = staircases.find(name);
    mine.push_back(rank() == 0 && value != staircases.end() ? value->second : 0.0);
  }
  for (double e : elo) mine.push_back(rank() == 0 ? e : 0);
  const std::vector<double> all = comm.all_gather(mine, "agreeing on the steps");  // [W][stride]
  const size_t stride = mine.size();
  for (int b = 0; b < nb; ++b) {
    double decisions = 0, buffered = 0, fewest = all[2 * b + 1];
    for (int r = 0; r < world; ++r) {
      decisions += all[r * stride + 2 * b];
      buffered += all[r * stride + 2 * b + 1];
      fewest = std::min(fewest, all[r * stride + 2 * b + 1]);
    }
    OnPolicyTrainer& t = *trainers_[b];
    synced_step_[b] += int64_t(decisions);
    t.set_step(synced_step_[b]);
    // the buffers hold buffer_size together, and each rank at least its share of a minibatch
    const auto& hp = t.config().hyperparameters;
    ready_[b] = buffered >= double(hp.buffer_size) && fewest >= double(hp.batch_size / world);
  }
  if (rank() == 0) return;
  size_t at = 2 * size_t(nb);
  std::map<std::string, int> decided;
  for (const auto& [name, lesson] : lessons) decided[name] = int(all[at++]);
  std::map<std::string, double> decided_staircases;
  for (const auto& [name, lesson] : lessons) decided_staircases[name] = all[at++];
  const LessonUpdate u = parameters_.follow(decided, decided_staircases);
  pending_follow_.changed |= u.changed;
  pending_follow_.require_reset |= u.require_reset;
  self_play_->set_elo_state(std::vector<double>(all.begin() + at, all.begin() + at + elo.size()));
}

void TrainingRun::check_replicas(int b) {
  OnPolicyTrainer& t = *trainers_[b];
  // a fault-injection hook for the tests' negative control: this rank drifts by one ulp
  if (const char* drift = std::getenv("RLT_TEST_DRIFT_RANK"); drift && std::atoi(drift) == rank()) {
    torch::Tensor p = t.flat_parameters();  // [P], shares the storage
    p[0] = std::nextafter(p[0].item<float>(), 1e30f);
  }
  // the hash in two exact halves (a double holds 53 bits)
  const uint64_t hash = tensor_hash(t.flat_parameters());
  const std::vector<double> all = options_.communicator->all_gather(
      {double(hash >> 32), double(hash & 0xffffffffu)}, "comparing the replicas");
  for (int r = 1; r < options_.communicator->world_size(); ++r)
    if (all[2 * r] != all[0] || all[2 * r + 1] != all[1])
      throw std::runtime_error("behavior " + t.behavior() + ", update " +
                               std::to_string(t.updates()) + ": the parameters of rank " +
                               std::to_string(r) + " differ from rank 0's");
}

void TrainingRun::reset_self_play() {
  std::vector<OnPolicyTrainer*> trainers;
  for (auto& t : trainers_) trainers.push_back(t.get());
  self_play_ = std::make_unique<SelfPlay>(trainers, seed_ * 7717 + 3);
}

void TrainingRun::boundary(bool final) {
  for (int b = 0; b < num_trainers(); ++b) {
    trainers_[b]->interrupt_all(env_->buffers(b));
    const auto& c = trainers_[b]->config();
    while (next_checkpoint_[b] <= trainers_[b]->step()) next_checkpoint_[b] += c.checkpoint_interval;
  }
  ++boundary_index_;
  if (folder_) {
    save_checkpoint();
    if (final) {
      export_policies();
      status_.finished = true;
      folder_->write_status(status_);
    }
  }
  if (!final) {
    sample_all_parameters();
    env_->reseed_and_reset(boundary_seed(boundary_index_));
    env_->stagger(config_.env_settings.stagger_steps);
  }
}

Parameters TrainingRun::next_parameters() {
  Parameters p = turn_fallback_;
  for (const auto& [name, value] : parameters_.sample(parameter_rng_)) p[name] = value;
  for (const auto& [name, value] : self_play_->turn_parameters()) p[name] = value;
  return p;
}

void TrainingRun::sample_all_parameters() {
  if (parameters_.empty() && turn_fallback_.empty()) return;
  for (int i = 0; i < env_->num_envs(); ++i) env_->set_parameters(i, next_parameters());
  std::fill(episode_epoch_.begin(), episode_epoch_.end(), lesson_epoch_);
  std::fill(episode_turn_.begin(), episode_turn_.end(), self_play_->team_changes());
}

int64_t TrainingRun::command_line_max_steps(const std::string& behavior) const {
  const auto named = options_.behavior_max_steps.find(behavior);
  return named != options_.behavior_max_steps.end() ? named->second : options_.max_steps;
}

void TrainingRun::apply_step_budgets() {
  for (auto& t : trainers_) {
    if (command_line_max_steps(t->behavior()) > 0) continue;  // over the lessons' budgets
    t->set_max_steps(parameters_.max_steps(t->behavior(), config_.behaviors.at(t->behavior()).max_steps));
  }
}

void TrainingRun::update_curriculum(const std::vector<FinishedEpisode>& finished,
                                    const std::vector<EpisodeStats>& episodes) {
  if (parameters_.empty()) {
    // no curriculum: instances that just ended an episode may still change turn parameters
    if (!turn_fallback_.empty())
      for (const auto& f : finished) env_->set_parameters(f.env_index, next_parameters());
    return;
  }
  for (int b = 0; b < num_trainers(); ++b)
    for (float r : episodes[b].returns) parameters_.add_episode_reward(trainers_[b]->behavior(), r);
  // a metric measures the lesson it was played in: episodes begun before the last change are left
  // out. Criteria that name a behavior count an episode only when that behavior learned from all
  // of it: with self-play, an episode played entirely in one of its turns (the other team's turns
  // may be played in another setting, their turn_parameters)
  std::vector<std::string> learners;  // the behaviors learning in this turn
  if (!finished.empty())
    for (int b = 0; b < num_trainers(); ++b)
      if (self_play_->learns(b)) learners.push_back(trainers_[b]->behavior());
  for (const auto& f : finished) {
    if (episode_epoch_[f.env_index] != lesson_epoch_) continue;
    const bool one_turn = episode_turn_[f.env_index] == self_play_->team_changes();
    parameters_.add_episode_metrics(f.metrics, one_turn ? learners : std::vector<std::string>{});
  }
  std::map<std::string, BehaviorProgress> progress;
  for (auto& t : trainers_) progress[t->behavior()] = {t->step(), t->config().max_steps};
  // data-parallel: rank 0 decides; the others moved to its lessons in sync_ranks
  std::set<std::string> emerged;
  for (const Emergence& e : strategies_.emergences())
    if (e.step >= 0) emerged.insert(e.strategy);
  const LessonUpdate u = rank() == 0 ? parameters_.update(progress, emerged) : pending_follow_;
  pending_follow_ = LessonUpdate{};
  log_lesson_changes(u.changes);
  for (const std::string& sentence : u.fallbacks) *log_ << sentence << "\n";
  for (const std::string& sentence : u.waits) *log_ << sentence << "\n";
  if (u.changed) {
    ++lesson_epoch_;
    apply_step_budgets();
  }
  if (u.changed && u.require_reset) {
    // a lesson that asks for it restarts every episode now, from a deterministic point
    for (int b = 0; b < num_trainers(); ++b) trainers_[b]->interrupt_all(env_->buffers(b));
    ++lesson_resets_;
    sample_all_parameters();
    env_->reseed_and_reset(
        derived_seed(boundary_seed(boundary_index_), uint64_t(lesson_resets_)));
    env_->stagger(config_.env_settings.stagger_steps);
    return;
  }
  // instances that just ended an episode get fresh values for their next reset
  for (const auto& f : finished) {
    env_->set_parameters(f.env_index, next_parameters());
    episode_epoch_[f.env_index] = lesson_epoch_;
    episode_turn_[f.env_index] = self_play_->team_changes();
  }
}

void TrainingRun::save_checkpoint() {
  torch::serialize::OutputArchive archive;
  write_vector(archive, "run.boundary_index", std::vector<int64_t>{boundary_index_});
  write_vector(archive, "run.elapsed", std::vector<double>{elapsed()});
  for (int b = 0; b < num_trainers(); ++b) {
    torch::serialize::OutputArchive ba;
    trainers_[b]->save(ba);
    write_vector(ba, "summary_returns", summary_returns_[b]);
    write_vector(ba, "summary_group_returns", summary_group_returns_[b]);
    write_vector(ba, "window.returns", update_window_[b].returns);
    write_vector(ba, "window.lengths", update_window_[b].lengths);
    // what the next summary line and TensorBoard point average besides the returns
    write_vector(ba, "summary.lengths", summary_lengths_[b]);
    write_metric_sums(ba, "summary.metrics", summary_metrics_[b], 0);
    const UpdateSums& u = summary_updates_[b];
    write_vector(ba, "summary.updates",
                 std::vector<double>{u.policy_loss, u.value_loss, u.baseline_loss, u.entropy,
                                     u.learning_rate, u.epsilon, u.beta, double(u.count),
                                     u.approx_kl, u.clip_fraction});
    const LastSummary& last = last_summary_[b];
    write_vector(ba, "summary.last",
                 std::vector<double>{double(last.any), last.reward, last.group_reward, last.length,
                                     double(last.episodes)});
    archive.write("behavior." + trainers_[b]->behavior(), ba);
  }
  for (int i = 0; i < int(strategies_.strategies().size()); ++i) {
    const Emergence& e = strategies_.emergences()[i];
    write_vector(archive, "strategy." + e.strategy + ".window", strategies_.save_window(i));
    write_vector(archive, "strategy." + e.strategy + ".emerged",
                 std::vector<double>{double(e.step), e.elapsed_s, e.rate});
  }
  write_string(archive, "run.parameters", parameters_.serialize());
  write_vector(archive, "run.lesson_resets", std::vector<int64_t>{lesson_resets_});
  // the env episodes since the last row of metrics/episodes.csv: a boundary need not fall on a
  // summary, and a resumed run's next row counts them as the uninterrupted run's does
  write_metric_sums(archive, "run.episode_window", episode_window_, episode_window_count_);
  {
    std::ostringstream rng;
    rng << parameter_rng_;
    write_string(archive, "run.parameter_rng", rng.str());
  }
  if (self_play_->enabled()) {
    torch::serialize::OutputArchive sp;
    self_play_->save(sp);
    archive.write("selfplay", sp);
  }
  CheckpointEntry entry;
  entry.index = boundary_index_;
  entry.file = "checkpoints/checkpoint-" + std::to_string(boundary_index_) + ".pt";
  entry.elapsed_seconds = elapsed();
  for (auto& t : trainers_) entry.steps[t->behavior()] = t->step();
  const std::string path = folder_->file(entry.file);
  // serialized in memory first: LibTorch's file writer reports a failed write (a full disk) from
  // a destructor, which ends the process; our own write reports it as an error, and the run's
  // earlier checkpoints stay as they were
  std::ostringstream bytes;
  archive.save_to(bytes);
  write_file_atomically(path, bytes.str());
  status_.checkpoints.push_back(entry);
  status_.lessons = parameters_.lessons();
  status_.strategies = strategies_.emergences();
  status_.elo.clear();
  for (int b = 0; b < num_trainers(); ++b)
    if (trainers_[b]->config().self_play) status_.elo[trainers_[b]->behavior()] = self_play_->elo(b);
  // newest keep_checkpoints stay; the status names only files that exist
  int keep = 1;
  for (auto& t : trainers_) keep = std::max(keep, t->config().keep_checkpoints);
  std::vector<std::string> removed;
  while (int(status_.checkpoints.size()) > keep) {
    removed.push_back(status_.checkpoints.front().file);
    status_.checkpoints.erase(status_.checkpoints.begin());
  }
  folder_->write_status(status_);
  for (const auto& f : removed) fs::remove(folder_->file(f));
}

void TrainingRun::load_checkpoint(const std::string& path, bool weights_only) {
  torch::serialize::InputArchive archive;
  try {
    archive.load_from(path);
  } catch (const c10::Error& e) {
    throw std::runtime_error("cannot read checkpoint " + path + ": " + e.what_without_backtrace());
  }
  for (int b = 0; b < num_trainers(); ++b) {
    torch::serialize::InputArchive ba;
    if (!archive.try_read("behavior." + trainers_[b]->behavior(), ba))
      throw std::runtime_error("checkpoint " + path + " has no behavior " + trainers_[b]->behavior());
    if (weights_only) {
      trainers_[b]->load_weights(ba);
      continue;
    }
    trainers_[b]->load(ba);
    summary_returns_[b] = read_vector<float>(ba, "summary_returns");
    summary_group_returns_[b] = read_vector<float>(ba, "summary_group_returns");
    update_window_[b].returns = read_vector<float>(ba, "window.returns");
    update_window_[b].lengths = read_vector<float>(ba, "window.lengths");
    // older checkpoints: the next summary averages only what comes after the resume
    summary_lengths_[b].clear();
    summary_metrics_[b].clear();
    summary_updates_[b] = UpdateSums{};
    last_summary_[b] = LastSummary{};
    int64_t unused = 0;
    if (read_metric_sums(ba, "summary.metrics", summary_metrics_[b], unused)) {
      summary_lengths_[b] = read_vector<float>(ba, "summary.lengths");
      const auto u = read_vector<double>(ba, "summary.updates");
      summary_updates_[b] = {u.at(0), u.at(1), u.at(2), u.at(3), u.at(4), u.at(5), u.at(6)};
      summary_updates_[b].count = int(u.at(7));
      if (u.size() > 9) {  // checkpoints written before these two were kept leave them 0
        summary_updates_[b].approx_kl = u[8];
        summary_updates_[b].clip_fraction = u[9];
      }
      const auto last = read_vector<double>(ba, "summary.last");
      last_summary_[b] = {last.at(0) != 0, last.at(1), last.at(2), last.at(3),
                          int64_t(last.at(4))};
    }
  }
  if (!weights_only) {
    if (self_play_->enabled()) {
      torch::serialize::InputArchive sp;
      if (!archive.try_read("selfplay", sp))
        throw std::runtime_error("checkpoint " + path + " has no self-play state");
      self_play_->load(sp);
    }
    std::vector<Emergence> emerged = strategies_.emergences();
    for (int i = 0; i < int(emerged.size()); ++i) {
      const std::string key = "strategy." + emerged[i].strategy;
      strategies_.load_window(i, read_vector<float>(archive, key + ".window"));
      const auto e = read_vector<double>(archive, key + ".emerged");
      emerged[i].step = int64_t(e.at(0));
      emerged[i].elapsed_s = e.at(1);
      emerged[i].rate = e.at(2);
    }
    strategies_.set_emergences(emerged);
    status_.strategies = emerged;
    parameters_.deserialize(read_string(archive, "run.parameters"));
    apply_step_budgets();
    lesson_resets_ = read_vector<int64_t>(archive, "run.lesson_resets").at(0);
    episode_window_.clear();  // older checkpoints: an empty window
    episode_window_count_ = 0;
    read_metric_sums(archive, "run.episode_window", episode_window_, episode_window_count_);
    std::istringstream rng(read_string(archive, "run.parameter_rng"));
    rng >> parameter_rng_;
    boundary_index_ = read_vector<int64_t>(archive, "run.boundary_index").at(0);
    elapsed_before_ = read_vector<double>(archive, "run.elapsed").at(0);
  }
}

void TrainingRun::export_policies() {
  for (auto& t : trainers_)
    export_policy(*t->network(), t->normalizer(), t->spec(), folder_->policy_path(t->behavior()));
}

void TrainingRun::log_update(int b, const UpdateStats& s) {
  UpdateSums& sums = summary_updates_[b];
  sums.policy_loss += s.policy_loss;
  sums.value_loss += s.value_loss;
  sums.baseline_loss += s.baseline_loss;
  sums.entropy += s.entropy;
  sums.learning_rate += s.learning_rate;
  sums.epsilon += s.epsilon;
  sums.beta += s.beta;
  sums.approx_kl += s.approx_kl;
  sums.clip_fraction += s.clip_fraction;
  ++sums.count;
  auto& w = update_window_[b];
  if (folder_) {
    std::ostringstream out;
    out << trainers_[b]->step() << ',' << elapsed() << ',' << w.returns.size() << ','
        << mean_of(w.returns) << ',' << std_of(w.returns) << ',' << mean_of(w.lengths) << ','
        << s.policy_loss << ',' << s.value_loss << ',' << s.baseline_loss << ',' << s.entropy << ','
        << s.learning_rate << ',' << s.epsilon << ',' << s.beta << ',';
    if (trainers_[b]->config().self_play) out << self_play_->elo(b);  // else empty
    out << ',' << s.approx_kl << ',' << s.clip_fraction << '\n';
    append_to_file(folder_->metrics_path(trainers_[b]->behavior()), out.str());
  }
  w = EpisodeStats{};
}

void TrainingRun::summarize(int b) {
  auto& t = *trainers_[b];
  auto& returns = summary_returns_[b];
  std::ostringstream os;
  os << std::fixed << std::setprecision(3) << "[" << t.behavior() << "] Step: " << t.step()
     << ". Time Elapsed: " << elapsed() << " s.";
  if (returns.empty()) {
    os << " No episode was completed since last summary.";
  } else {
    const auto& group = summary_group_returns_[b];
    const LastSummary& last = last_summary_[b] = {true, mean_of(returns), mean_of(group),
                                                  mean_of(summary_lengths_[b]),
                                                  int64_t(returns.size())};
    os << " Mean Reward: " << last.reward << ". Std of Reward: " << std_of(returns) << ".";
    if (std::any_of(group.begin(), group.end(), [](float g) { return g != 0.f; }))
      os << " Mean Group Reward: " << last.group_reward << ".";
    os << " Episodes: " << returns.size() << ".";
  }
  if (t.config().self_play) os << " ELO: " << self_play_->elo(b) << ".";
  for (const auto& [name, lesson] : parameters_.lessons()) os << " Lesson " << name << ": " << lesson << ".";
  for (const auto& [name, value] : parameters_.staircase_values())
    os << " Staircase " << name << ": " << value << ".";
  for (const auto& [name, sum_count] : summary_metrics_[b])
    os << " " << name << ": " << sum_count.first / sum_count.second << ".";
  for (int i = 0; i < int(strategies_.strategies().size()); ++i) {
    const StrategySpec& st = strategies_.strategies()[i];
    if (st.behavior != t.behavior()) continue;
    const Emergence& e = strategies_.emergences()[i];
    os << " Strategy " << st.name << ": " << std::setprecision(3) << strategies_.rate(i);
    if (e.step >= 0) os << " (emerged at step " << e.step << ")";
    os << ".";
  }
  const double frac = double(t.step()) / double(t.config().max_steps);
  if (frac > 0 && frac < 1) os << " ETA: " << std::setprecision(0) << elapsed() * (1 - frac) / frac << " s.";
  os << (t.finished() ? "" : " Training.");
  write_tensorboard(b);
  returns.clear();
  summary_group_returns_[b].clear();
  summary_lengths_[b].clear();
  summary_updates_[b] = UpdateSums{};
  summary_metrics_[b].clear();
  log_episode_metrics();
  if (options_.progress && isatty(2)) std::cerr << "\r\033[K";
  *log_ << os.str() << std::endl;
  last_progress_ = -1;
}

void TrainingRun::write_tensorboard(int b) {
  if (!folder_) return;
  const OnPolicyTrainer& t = *trainers_[b];
  if (!tensorboard_[b])
    tensorboard_[b] = std::make_unique<TensorBoardWriter>(folder_->file(t.behavior()));
  // ML-Agents' tag names, so dashboards built for it work unchanged
  std::vector<std::pair<std::string, float>> scalars;
  if (!summary_returns_[b].empty()) {  // episodes since the last summary: last_summary_ is theirs
    const LastSummary& last = last_summary_[b];
    scalars.emplace_back("Environment/Cumulative Reward", float(last.reward));
    scalars.emplace_back("Environment/Episode Length", float(last.length));
    if (t.config().trainer_type == "poca")
      scalars.emplace_back("Environment/Group Cumulative Reward", float(last.group_reward));
  }
  const UpdateSums& u = summary_updates_[b];
  if (u.count > 0) {
    const double n = u.count;
    scalars.emplace_back("Losses/Policy Loss", float(u.policy_loss / n));
    scalars.emplace_back("Losses/Value Loss", float(u.value_loss / n));
    if (t.config().trainer_type == "poca")
      scalars.emplace_back("Losses/Baseline Loss", float(u.baseline_loss / n));
    scalars.emplace_back("Policy/Entropy", float(u.entropy / n));
    scalars.emplace_back("Policy/Learning Rate", float(u.learning_rate / n));
    scalars.emplace_back("Policy/Epsilon", float(u.epsilon / n));
    scalars.emplace_back("Policy/Beta", float(u.beta / n));
    scalars.emplace_back("Policy/Approx KL", float(u.approx_kl / n));
    scalars.emplace_back("Policy/Clip Fraction", float(u.clip_fraction / n));
  }
  if (t.config().self_play) scalars.emplace_back("Self-play/ELO", float(self_play_->elo(b)));
  for (const auto& [name, lesson] : parameters_.lessons())
    scalars.emplace_back("Environment/Lesson Number/" + name, float(lesson));
  for (const auto& [name, value] : parameters_.staircase_values())
    scalars.emplace_back("Environment/Staircase/" + name, float(value));
  for (const auto& [name, sum_count] : summary_metrics_[b])
    scalars.emplace_back("Environment/" + name, float(sum_count.first / sum_count.second));
  for (int i = 0; i < int(strategies_.strategies().size()); ++i) {
    const StrategySpec& st = strategies_.strategies()[i];
    if (st.behavior == t.behavior())
      scalars.emplace_back("Strategy/" + st.name, float(strategies_.rate(i)));
  }
  tensorboard_[b]->add_scalars(t.step(), scalars);
}

namespace {

// 1234567 -> "1,234,567"
std::string with_commas(int64_t n) {
  std::string digits = std::to_string(n < 0 ? -n : n), out;
  for (size_t i = 0; i < digits.size(); ++i) {
    if (i > 0 && (digits.size() - i) % 3 == 0) out += ',';
    out += digits[i];
  }
  return (n < 0 ? "-" : "") + out;
}

std::string fixed(double value, int decimals) {
  std::ostringstream os;
  os << std::fixed << std::setprecision(decimals) << value;
  return os.str();
}

// rows of cells as a plain-text table, columns padded to their widest cell, a rule under row 0
std::string text_table(const std::vector<std::vector<std::string>>& rows) {
  std::vector<size_t> width;
  for (const auto& row : rows)
    for (size_t i = 0; i < row.size(); ++i) {
      if (width.size() <= i) width.push_back(0);
      width[i] = std::max(width[i], row[i].size());
    }
  std::string out;
  for (size_t r = 0; r < rows.size(); ++r) {
    std::string line = "  ";
    for (size_t i = 0; i < rows[r].size(); ++i)
      line += rows[r][i] + std::string(width[i] - rows[r][i].size() + 2, ' ');
    out += line.substr(0, line.find_last_not_of(' ') + 1) + "\n";
    if (r == 0) {
      size_t total = 0;
      for (size_t w : width) total += w + 2;
      out += "  " + std::string(total - 2, '-') + "\n";
    }
  }
  return out;
}

}  // namespace

std::string TrainingRun::summary_table() const {
  std::vector<std::vector<std::string>> rows = {
      {"behavior", "trainer", "steps", "episodes", "mean reward", "group reward", "ELO"}};
  for (int b = 0; b < num_trainers(); ++b) {
    const OnPolicyTrainer& t = *trainers_[b];
    const LastSummary& last = last_summary_[b];
    const bool poca = t.config().trainer_type == "poca";
    rows.push_back({t.behavior(), t.config().trainer_type, with_commas(t.step()),
                    last.any ? with_commas(last.episodes) : "-",
                    last.any ? fixed(last.reward, 3) : "-",
                    last.any && poca ? fixed(last.group_reward, 3) : "-",
                    t.config().self_play ? fixed(self_play_->elo(b), 0) : "-"});
  }
  std::string out = "Summary (rewards of the last summary's episodes)\n" + text_table(rows);
  const auto names = parameters_.lesson_names();
  for (const auto& [name, lesson] : parameters_.lessons())
    out += "Lesson " + name + ": " + std::to_string(lesson) + " (" + names.at(name) + ")\n";
  for (const auto& [name, value] : parameters_.staircase_values())
    out += "Staircase " + name + ": " + fixed(value, 3) + "\n";
  if (!strategies_.empty()) {
    std::vector<std::vector<std::string>> s = {
        {"strategy", "behavior", "metric", "rate", "emerged at step", "after"}};
    for (int i = 0; i < int(strategies_.strategies().size()); ++i) {
      const StrategySpec& st = strategies_.strategies()[i];
      const Emergence& e = strategies_.emergences()[i];
      std::string metric = st.metric;
      if (!st.conditions.empty()) metric += " (" + st.describe_conditions() + ")";
      s.push_back({st.name, st.behavior, metric, fixed(strategies_.rate(i), 3),
                   e.step >= 0 ? with_commas(e.step) : "not yet",
                   e.step >= 0 ? fixed(e.elapsed_s / 60.0, 1) + " min" : "-"});
    }
    out += text_table(s);
  }
  if (folder_) {
    out += "Policies:";
    for (const auto& t : trainers_) out += " " + folder_->policy_path(t->behavior());
    out += "\nTensorBoard: tensorboard --logdir " +
           std::filesystem::path(folder_->path()).parent_path().string() + "\n";
  }
  return out;
}

int64_t TrainingRun::total_steps() const {
  int64_t n = 0;
  for (const auto& t : trainers_) n += t->step();
  return n;
}

void TrainingRun::check_until_emerged() const {
  if (options_.until_emerged.empty()) return;
  if (distributed())
    throw std::invalid_argument(
        "--until-emerged: not with data-parallel training (each rank dates strategies from its "
        "own episodes); stop the run with --max-steps");
  std::string known;
  for (const StrategySpec& s : env_->spec().strategies) known += (known.empty() ? "" : ", ") + s.name;
  for (const std::string& name : options_.until_emerged) {
    const auto& all = env_->spec().strategies;
    if (std::none_of(all.begin(), all.end(), [&](const StrategySpec& s) { return s.name == name; }))
      throw std::invalid_argument("--until-emerged " + name + ": environment " + env_->spec().name +
                                  " declares no strategy '" + name + "' (it declares: " +
                                  (known.empty() ? "none" : known) + ")");
  }
}

bool TrainingRun::awaited_strategies_emerged() const {
  if (options_.until_emerged.empty()) return false;
  for (const std::string& name : options_.until_emerged)
    for (const Emergence& e : strategies_.emergences())
      if (e.strategy == name && e.step < 0) return false;
  return true;
}

void TrainingRun::track_episodes(const std::vector<FinishedEpisode>& finished) {
  if (finished.empty()) return;
  std::map<std::string, int64_t> steps;
  for (const auto& t : trainers_) steps[t->behavior()] = t->step();
  bool emerged_any = false;
  for (const auto& f : finished) {
    ++episode_window_count_;
    for (const auto& [name, value] : f.metrics) {
      episode_window_[name].first += value;
      episode_window_[name].second += 1;
    }
    if (strategies_.empty()) continue;
    auto parameter = [&](const std::string& name) { return env_->parameter(f.env_index, name); };
    for (int i : strategies_.add_episode(f.metrics, parameter, steps, elapsed())) {
      const Emergence& e = strategies_.emergences()[i];
      const StrategySpec& s = strategies_.strategies()[i];
      if (options_.progress && isatty(2)) std::cerr << "\r\033[K";
      *log_ << std::fixed << std::setprecision(3) << "[" << e.behavior << "] Strategy "
            << e.strategy << " emerged at step " << e.step << " (" << std::setprecision(0)
            << e.elapsed_s << " s): " << s.metric << std::setprecision(3) << " " << e.rate
            << " over the last " << s.window << " episodes"
            << (s.conditions.empty() ? "" : " with " + s.describe_conditions()) << "." << std::endl;
      emerged_any = true;
    }
  }
  if (emerged_any && folder_) {
    status_.strategies = strategies_.emergences();
    folder_->write_status(status_);
  }
}

std::string TrainingRun::episode_metrics_header() const {
  std::ostringstream out;
  out << "total_steps,elapsed_s,episodes";
  for (const auto& t : trainers_) out << ',' << t->behavior() << "_step";
  for (const auto& [name, lesson] : parameters_.lessons()) out << ",lesson_" << name;
  for (const std::string& name : env_->episode_metric_names()) out << ',' << name;
  for (const auto& s : strategies_.strategies()) out << ",smoothed_" << s.metric << "_" << s.name;
  out << '\n';
  return out.str();
}

std::string TrainingRun::lesson_changes_header() const {
  std::ostringstream out;
  out << "total_steps,elapsed_s";
  for (const auto& t : trainers_) out << ',' << t->behavior() << "_step";
  out << ",parameter,from_lesson,to_lesson,change,measure\n";
  return out.str();
}

void TrainingRun::log_lesson_changes(const std::vector<LessonChange>& changes) {
  if (!folder_ || changes.empty()) return;
  const std::string path = folder_->lesson_changes_path();
  std::ostringstream out;
  if (!fs::exists(path) || fs::file_size(path) == 0) out << lesson_changes_header();
  for (const LessonChange& c : changes) {
    out << total_steps() << ',' << elapsed();
    for (const auto& t : trainers_) out << ',' << t->step();
    out << ',' << c.parameter << ',' << c.from << ',' << c.to << ','
        << (c.fell_back ? "fell_back" : "completed") << ',';
    if (std::isfinite(c.measure)) out << c.measure;
    out << '\n';
  }
  append_to_file(path, out.str());
}

void TrainingRun::log_episode_metrics() {
  if (!folder_ || episode_window_count_ == 0) return;
  const std::string path = folder_->episode_metrics_path();
  const bool fresh = !fs::exists(path) || fs::file_size(path) == 0;
  std::ostringstream out;
  if (fresh) out << episode_metrics_header();
  out << total_steps() << ',' << elapsed() << ',' << episode_window_count_;
  for (const auto& t : trainers_) out << ',' << t->step();
  for (const auto& [name, lesson] : parameters_.lessons()) out << ',' << lesson;
  for (const std::string& name : env_->episode_metric_names()) {
    out << ',';
    const auto it = episode_window_.find(name);
    if (it != episode_window_.end()) out << it->second.first / it->second.second;
  }
  for (int i = 0; i < int(strategies_.strategies().size()); ++i) out << ',' << strategies_.rate(i);
  out << '\n';
  append_to_file(path, out.str());
  episode_window_.clear();
  episode_window_count_ = 0;
}

void TrainingRun::show_progress(bool done) {
  if (!options_.progress || !isatty(2)) return;
  const double now = elapsed();
  if (!done && last_progress_ >= 0 && now - last_progress_ < 0.25) return;
  last_progress_ = now;
  double frac = 1;
  for (auto& t : trainers_)
    frac = std::min(frac, double(t->step()) / double(t->config().max_steps));
  frac = std::clamp(frac, 0.0, 1.0);
  const int width = 30, filled = int(frac * width);
  std::ostringstream os;
  os << "\r\033[K" << std::setw(3) << int(frac * 100) << "% [" << std::string(filled, '=')
     << std::string(width - filled, ' ') << "] ";
  for (auto& t : trainers_) os << t->behavior() << " " << t->step() << "/" << t->config().max_steps << "  ";
  os << std::fixed << std::setprecision(0) << now << " s";
  if (frac > 0 && frac < 1) os << ", ETA " << now * (1 - frac) / frac << " s";
  if (done) os << "\n";
  std::cerr << os.str() << std::flush;
}

}  // namespace rlt
