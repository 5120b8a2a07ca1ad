// Communicator on LibTorch's c10d: a TCPStore held by rank 0 for the rendezvous and a Gloo
// process group for the collectives, both with the launch's timeout, so a rank that dies makes
// the others stop with an error naming it instead of waiting forever.
#pragma once

#include <memory>

#include "rl/distributed/communicator.h"
#include "rl/distributed/launch_settings.h"

namespace rlt {

// Connects this rank to the others. Throws naming the problem when the master cannot be reached
// within the timeout, or when the ranks were launched with different WORLD_SIZE or the same RANK.
std::unique_ptr<Communicator> connect_gloo(const LaunchSettings& settings);

}  // namespace rlt
