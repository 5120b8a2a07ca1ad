// Where a rank of a distributed run finds the others: the environment variables torchrun and
// cluster launchers set (MASTER_ADDR, MASTER_PORT, WORLD_SIZE, RANK, LOCAL_RANK), as PyTorch reads
// them. No variables, or WORLD_SIZE=1: one process.
#pragma once

#include <string>

namespace rlt {

struct LaunchSettings {
  std::string master_addr = "127.0.0.1";  // where rank 0 listens (the store)
  int master_port = 29500;
  int world_size = 1;
  int rank = 0;
  int local_rank = 0;           // rank among the processes of this machine
  double timeout_seconds = 60;  // a rank silent this long makes the others stop

  bool distributed() const { return world_size > 1; }
};

// Reads the variables from the environment; throws naming the variable and its value when one is
// malformed or they disagree (RANK >= WORLD_SIZE, RANK without WORLD_SIZE, ...).
LaunchSettings launch_settings_from_environment();

}  // namespace rlt
