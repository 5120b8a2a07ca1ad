// What a run ran on: the CPU, the BLAS kernels, LibTorch and this program's source commit.
//
// A seed gives the same trajectory on one machine and build, not across them: rlt is compiled
// for the build machine's CPU and the learner's matrix products run on the kernels OpenBLAS picks
// for it, so two CPUs differ in the last bits of the updates and their runs part within the first
// updates (docs/results, nineteenth section: the default hide-and-seek file with seed 1 reached
// shelter at 2.37M hider steps on an Intel Xeon and 3.51M on an AMD EPYC). Training records this
// per session in training_status.json so that figures can be traced to the machine that produced
// them.
#pragma once

#include <string>

namespace rlt {

// the source tree's `git describe --always --dirty` when it was built ("unknown" without git);
// defined in a file the build writes (cmake/build_info.cmake)
const char* build_commit();

struct MachineInfo {
  std::string cpu;            // /proc/cpuinfo's model name ("unknown" where there is none)
  int cores = 0;              // hardware threads
  std::string blas_kernels;   // the family OpenBLAS runs ("" when the BLAS is another)
  std::string torch_version;  // LibTorch's
  std::string rlt_commit;     // build_commit()
};

MachineInfo current_machine();

// What differs between two machines in a way that changes trajectories (CPU, BLAS kernels,
// LibTorch, rlt's commit), e.g. "CPU Intel Xeon -> AMD EPYC, BLAS kernels SkylakeX -> Haswell";
// "" when nothing does. The number of cores alone changes nothing (threads are set per run).
std::string machine_difference(const MachineInfo& before, const MachineInfo& now);

}  // namespace rlt
