// The folder of one training run, results/<run-id>/:
//   configuration.yaml     the resolved configuration
//   training_status.json   checkpoints (newest last) with steps per behavior, curriculum lessons,
//                          self-play ELO, the step each of the env's strategies emerged at,
//                          whether training finished, and each session's machine (a start or a
//                          resume: when, from which steps, on which CPU, BLAS kernels and build)
//   checkpoints/           checkpoint-<index>.pt, written atomically (temporary file, then rename)
//   metrics/<Behavior>.csv one row per update: losses, schedules, episodes since the last row,
//                          self-play ELO
//   metrics/episodes.csv   one row per summary: steps, lessons and the means of the env's episode
//                          metrics (strategy rates) over the episodes since the last row
//   metrics/lessons.csv    one row per curriculum change, at the steps it happened: the
//                          parameter, the lessons left and entered, completed or fell back, and
//                          the measure that decided it
//   <Behavior>.pt          the exported TorchScript policy
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "rl/core/machine_info.h"
#include "rl/trainer/strategy_tracker.h"

namespace rlt {

struct CheckpointEntry {
  int64_t index = 0;                    // boundary number (1, 2, ...)
  std::string file;                     // relative to the run folder
  std::map<std::string, int64_t> steps; // per behavior
  double elapsed_seconds = 0;
};

// One start or resume of a run: a seed's trajectory holds on one machine and build only, so
// figures are traced to the machine that produced them.
struct RunSession {
  std::string started;                   // UTC, ISO 8601 (2026-11-27T02:10:00Z)
  std::map<std::string, int64_t> steps;  // per behavior, when the session began
  MachineInfo machine;
};

struct TrainingStatus {
  std::string run_id;
  std::map<std::string, int> lessons;    // curriculum lesson per parameter, at the newest checkpoint
  std::map<std::string, double> elo;     // self-play rating per behavior, at the newest checkpoint
  std::vector<CheckpointEntry> checkpoints;  // oldest first
  std::vector<Emergence> strategies;         // the env's strategies, emerged or not
  std::vector<RunSession> sessions;          // oldest first (none in status files from before them)
  bool finished = false;
};

class RunFolder {
 public:
  RunFolder(const std::string& results_dir, const std::string& run_id);

  const std::string& path() const { return path_; }
  const std::string& run_id() const { return run_id_; }
  std::string file(const std::string& relative) const { return path_ + "/" + relative; }
  std::string config_path() const { return file("configuration.yaml"); }
  std::string status_path() const { return file("training_status.json"); }
  std::string policy_path(const std::string& behavior) const { return file(behavior + ".pt"); }
  std::string metrics_path(const std::string& behavior) const {
    return file("metrics/" + behavior + ".csv");
  }
  std::string episode_metrics_path() const { return file("metrics/episodes.csv"); }
  std::string lesson_changes_path() const { return file("metrics/lessons.csv"); }
  bool exists() const;

  // Creates the folder for a new run. Throws when it exists, unless `force` (then it is emptied).
  void create(bool force) const;

  TrainingStatus read_status() const;  // throws naming the file when missing or corrupt
  void write_status(const TrainingStatus& status) const;  // atomic

 private:
  std::string path_, run_id_;
};

}  // namespace rlt
