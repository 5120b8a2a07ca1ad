#include <algorithm>
#include <iostream>
#include <set>
#include <thread>

#include "apps/command_line.h"
#include "apps/commands.h"
#include "apps/local_launcher.h"
#include "rl/config/config_parser.h"
#include "rl/distributed/gloo_communicator.h"
#include "rl/env_api/env_registry.h"
#include "rl/trainer/training_run.h"

namespace rlt {

const char* const kTrainHelp = R"(Usage: rlt train CONFIG [options]

Trains every behavior of the environment named by CONFIG's env_settings.env_id with the trainer of
its behaviors: entry. CONFIG may name a base_config (a path relative to CONFIG's folder, or
absolute; a base may name its own): CONFIG's keys are laid over the base's, mappings merging key
by key, a mapping over a curriculum's lessons changing the lessons it names (lesson name -> keys;
a new name with insert_before: NAME or insert_after: NAME adds a lesson, remove: true drops one),
a key given as `KEY: !remove` dropping the base's KEY, and other values (lists and null too)
replacing the base's. Writes results/<run-id>/:
configuration.yaml (the whole resolved configuration), checkpoints/, metrics/,
<Behavior>/events.out.tfevents.* (TensorBoard, ML-Agents' tags: tensorboard --logdir results),
training_status.json and <Behavior>.pt (TorchScript policies) at the end. Envs that declare
strategies (HideAndSeek: running_and_chasing, shelter) get their episode metrics in
metrics/episodes.csv and the step each strategy emerged at in training_status.json, which also
records each start or resume's machine (CPU, BLAS kernels, LibTorch, rlt commit): a seed gives the
same run only on one machine and build, and a resume on another says so. Each curriculum change
is a row of metrics/lessons.csv at the steps it happened (rlt lessons reads it). Prints a
summary line per behavior every summary_freq steps, a progress bar with the time left (on a
terminal), and at the end a table of steps, rewards, ELO, lessons and strategies.
env_settings.stagger_steps S (default 0) spreads the env instances over their episodes: after
every start and checkpoint instance i first plays i x S / num_envs still steps, not learned from.
A behavior's self_play.turn_parameters hold for the episodes begun while its team learns.
A lesson's behavior_max_steps ({Seeker: 2000000}) raises those behaviors' max_steps from that
lesson on, so a behavior that had finished takes turns again. A completion_criteria's
fallback_threshold (with fallback_length, in episodes) sends a lesson back to the one before when
its measure over the last episodes falls to it; the log names the lessons and the measure.
A lesson's staircase ({parameter: P, end: E, step_up: U, step_down: D}) starts P at the
lesson's value and moves it U toward E after each counted episode above the criteria's
threshold and D back after any other; the lesson ends when P reaches E (with --nproc, rank 0's
episodes move it).
Every lesson's values (both ends of a staircase) are tried on the envs before training: one
the env rejects is an error naming the parameter and the lesson.

Options:
  --run-id ID            run folder name (default: checkpoint_settings.run_id)
  --results-dir DIR      parent folder of runs (default: results)
  --resume               continue the run from its newest checkpoint
  --force                overwrite an existing run folder
  --initialize-from ID   start from the weights of run ID's newest checkpoint
  --num-envs N           environment instances (default: env_settings.num_envs)
  --seed S               base seed; instance i's seed mixes S and i (default:
                         env_settings.seed, else 0; with --resume the seed the run began with)
  --max-steps N          steps per behavior, overriding max_steps and lessons'
                         behavior_max_steps
  --max-steps NAME=N     steps of behavior NAME alone (repeat; over a plain --max-steps N), e.g.
                         --resume --max-steps Hider=3000000 lengthens a run without the seekers
                         learning again
  --until-emerged NAME   stop, as at max_steps (a last checkpoint, the policies exported), once
                         the env's strategy NAME has emerged (repeat: once every one has), e.g.
                         --until-emerged shelter; not kept by --resume, not with --nproc
  --param NAME=VALUE     set an env parameter over env_settings.params (repeat; not one that
                         environment_parameters sets, itself or in a lesson's
                         other_parameters, nor one in a behavior's
                         self_play.turn_parameters), e.g. --param unseen_reward=-0.001
  --threads T            environment threads (default: all cores); the learner's matrix products
                         use them too when the network is large (first layer >= 65536 weights)
  --nproc N              train with N data-parallel ranks on this machine (see below)
  --dist-timeout S       seconds a rank may stay silent before the others stop (default 60)
  --print-config         print the whole configuration CONFIG resolves to, its base_config laid
                         under, and exit (takes no other option; a run's configuration.yaml also
                         holds the options given and, with default_settings, the env's other
                         behaviors; the env does not check the lessons' values here)
An existing run id without --resume or --force is an error that touches nothing. A checkpoint
or metrics row that cannot be written (a full disk) stops training with an error and leaves no
partial file or row; --resume goes on from the newest complete checkpoint.

Distributed training (LibTorch's c10d with Gloo): every rank runs its own env_settings.num_envs
environments and a replica of each learner; gradients are averaged over the ranks, so every rank
applies the same update. buffer_size and batch_size are totals over the ranks. Rank 0 writes the
run folder. The ranks find each other through torchrun's variables (MASTER_ADDR, MASTER_PORT,
WORLD_SIZE, RANK, LOCAL_RANK), so `torchrun --no_python --nproc_per_node 2 rlt train CONFIG` or a
cluster launcher can start them; --nproc N starts N local ranks itself. A rank that dies makes the
others stop within --dist-timeout with an error naming it; --resume continues from the last
checkpoint.
)";

// --max-steps N (every behavior, once) and --max-steps NAME=N (one behavior, repeatable)
static void read_max_steps(const CommandLine& cl, TrainOptions& opt) {
  for (const std::string& v : cl.values("--max-steps")) {
    const auto eq = v.find('=');
    const std::string name = eq == std::string::npos ? "" : v.substr(0, eq);
    const std::string number = eq == std::string::npos ? v : v.substr(eq + 1);
    if (eq == 0) throw UsageError("--max-steps expects N or BEHAVIOR=N, got '" + v + "'");
    const long long n = parse_integer(number, "--max-steps " + v, 1);
    if (name.empty()) {
      if (opt.max_steps > 0) throw UsageError("--max-steps N given twice");
      opt.max_steps = n;
    } else {
      if (opt.behavior_max_steps.count(name)) throw UsageError("--max-steps " + name + " given twice");
      opt.behavior_max_steps[name] = n;
    }
  }
}

int run_train(const std::vector<std::string>& args) {
  const std::set<std::string> switches = {"--resume", "--force"};
  const std::set<std::string> options = {"--run-id",  "--results-dir", "--initialize-from",
                                         "--num-envs", "--seed",       "--max-steps",
                                         "--threads",  "--param",      "--nproc",
                                         "--dist-timeout", "--until-emerged"};
  std::set<std::string> all_switches = switches;
  all_switches.insert("--print-config");
  CommandLine cl(args, all_switches, options);
  if (cl.positional().size() != 1) throw UsageError("expected one CONFIG file");
  const bool print_config = cl.has("--print-config");
  if (print_config) {
    for (const auto* flags : {&switches, &options}) {
      for (const std::string& flag : *flags) {
        if (cl.has(flag)) throw UsageError("--print-config takes CONFIG alone, not " + flag);
      }
    }
  }
  LaunchSettings launch = launch_settings_from_environment();
  launch.timeout_seconds = cl.number("--dist-timeout", 60, 1);
  const int nproc = int(cl.integer("--nproc", 1, 1));
  if (nproc > 1) {
    if (launch.distributed())
      throw UsageError("--nproc starts its own ranks, but WORLD_SIZE=" +
                       std::to_string(launch.world_size) + " is set: use one or the other");
    return launch_local_ranks(nproc, rank_command("train", args, nproc),
                              launch.timeout_seconds + 10);
  }
  TrainOptions opt;
  opt.run_id = cl.value("--run-id");
  opt.results_dir = cl.value("--results-dir");
  opt.resume = cl.has("--resume");
  opt.force = cl.has("--force");
  if (opt.resume && opt.force) throw UsageError("--resume and --force exclude each other");
  opt.initialize_from = cl.value("--initialize-from");
  for (const std::string& name : cl.values("--until-emerged")) {
    if (std::find(opt.until_emerged.begin(), opt.until_emerged.end(), name) != opt.until_emerged.end())
      throw UsageError("--until-emerged " + name + " given twice");
    opt.until_emerged.push_back(name);
  }
  opt.num_envs = int(cl.integer("--num-envs", 0, 1));
  opt.seed = cl.integer("--seed", -1, 0);
  read_max_steps(cl, opt);
  opt.threads = int(cl.integer("--threads", 0, 1));
  opt.params = cl.parameters();
  RunConfig config = load_run_config(cl.positional()[0]);
  // the parser does not know the registry: name the file and key of an unknown env here
  const std::string& env_id = config.env_settings.env_id;
  if (!EnvRegistry::instance().contains(env_id)) {
    std::string known;
    for (const auto& name : EnvRegistry::instance().names())
      known += (known.empty() ? "" : ", ") + name;
    throw ConfigError(config.source_file, "env_settings.env_id", 0,
                      "unknown environment '" + env_id + "' (known: " + known + ")");
  }
  if (print_config) {
    std::cout << run_config_to_yaml(config) << std::flush;
    return 0;
  }
  std::unique_ptr<Communicator> communicator;
  if (launch.distributed()) communicator = connect_gloo(launch);
  opt.communicator = communicator.get();
  TrainingRun run(std::move(config), opt);
  if (launch.rank != 0) {  // rank 0 reports for all
    run.train();
    return 0;
  }
  std::cout << "Training " << run.config().env_settings.env_id << " into " << run.folder()->path()
            << " (" << run.config().env_settings.num_envs << " environments";
  if (launch.distributed()) std::cout << " on each of " << launch.world_size << " ranks";
  std::cout << ")" << std::endl;
  auto result = run.train();
  std::cout << "Done in " << result.seconds << " s: " << result.agent_steps << " agent steps ("
            << int64_t(result.agent_steps / std::max(1e-9, result.seconds)) << "/s).\n"
            << run.summary_table() << std::flush;
  return 0;
}

}  // namespace rlt
