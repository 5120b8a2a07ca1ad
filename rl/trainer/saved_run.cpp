#include "rl/trainer/saved_run.h"

#include <filesystem>

#include "rl/config/config_parser.h"
#include "rl/core/archive_io.h"
#include "rl/env_api/env_registry.h"
#include "rl/trainer/trainer_factory.h"

namespace fs = std::filesystem;

namespace rlt {

namespace {

// "18 (Hider 2000000, Seeker 1600000), 19 (...)"
std::string list_checkpoints(const std::vector<CheckpointEntry>& checkpoints) {
  std::string out;
  for (const auto& c : checkpoints) {
    out += (out.empty() ? "" : ", ") + std::to_string(c.index) + " (";
    std::string steps;
    for (const auto& [behavior, step] : c.steps)
      steps += (steps.empty() ? "" : ", ") + behavior + " " + std::to_string(step);
    out += steps + ")";
  }
  return out;
}

}  // namespace

SavedRun load_saved_run(const std::string& run_dir, int64_t checkpoint_index) {
  fs::path dir = fs::path(run_dir).lexically_normal();
  if (dir.filename().empty()) dir = dir.parent_path();
  if (!fs::is_directory(dir)) throw std::runtime_error("run folder " + run_dir + " does not exist");
  SavedRun run;
  run.folder = std::make_unique<RunFolder>(dir.parent_path().empty() ? "." : dir.parent_path().string(),
                                           dir.filename().string());
  run.config = load_run_config(run.folder->config_path());
  auto status = run.folder->read_status();
  if (status.checkpoints.empty())
    throw std::runtime_error(run.folder->path() + " has no checkpoint yet");
  const CheckpointEntry* chosen = &status.checkpoints.back();
  if (checkpoint_index != 0) {
    chosen = nullptr;
    for (const auto& c : status.checkpoints)
      if (c.index == checkpoint_index) chosen = &c;
    if (!chosen)
      throw std::runtime_error(run.folder->path() + " has no checkpoint " +
                               std::to_string(checkpoint_index) + "; it keeps " +
                               list_checkpoints(status.checkpoints));
  }
  run.checkpoint = run.folder->file(chosen->file);
  auto env = EnvRegistry::instance().make(run.config.env_settings.env_id, run.config.env_settings.params);
  run.env_spec = env->spec();
  torch::serialize::InputArchive archive;
  try {
    archive.load_from(run.checkpoint);
  } catch (const c10::Error& e) {
    throw std::runtime_error("cannot read checkpoint " + run.checkpoint + ": " + e.what_without_backtrace());
  }
  run.parameters = EnvironmentParameterManager(run.config.environment_parameters);
  run.parameters.deserialize(read_string(archive, "run.parameters"));
  for (const auto& bs : run.env_spec.behaviors) {
    auto t = make_trainer(bs, behavior_config(run.config, bs.name), bs.agent_slots, 0,
                                          run.env_spec.name);
    torch::serialize::InputArchive ba;
    if (!archive.try_read("behavior." + bs.name, ba))
      throw std::runtime_error("checkpoint " + run.checkpoint + " has no behavior " + bs.name);
    t->load_weights(ba);
    run.trainers.push_back(std::move(t));
  }
  return run;
}

}  // namespace rlt
