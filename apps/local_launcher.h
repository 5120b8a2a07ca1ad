// `rlt train --nproc N`: starts N ranks of the same command on this machine, as torchrun does:
// each a copy of this program with MASTER_ADDR=127.0.0.1, a free MASTER_PORT, WORLD_SIZE=N,
// RANK and LOCAL_RANK set, then waits for them.
#pragma once

#include <string>
#include <vector>

namespace rlt {

// Runs `rlt <args>` as `nproc` ranks; returns 0 when every rank succeeded, else the first failing
// rank's exit status. A rank that fails makes the others stop on their own (their collectives
// fail); any still running `grace_seconds` later is killed.
int launch_local_ranks(int nproc, const std::vector<std::string>& args, double grace_seconds);

// What each rank runs for `rlt <command> <args>` given --nproc: the same without --nproc, and
// with --threads (cores / nproc) unless the arguments set it, so the ranks share the cores.
std::vector<std::string> rank_command(const std::string& command,
                                      const std::vector<std::string>& args, int nproc);

}  // namespace rlt
