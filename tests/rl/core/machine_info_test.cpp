// Machine info: this machine is described, and only what changes trajectories counts as a change.
#include "rl/core/machine_info.h"

#include <gtest/gtest.h>

namespace rlt {
namespace {

TEST(MachineInfoTest, DescribesThisMachineAndBuild) {
  const MachineInfo m = current_machine();
  EXPECT_FALSE(m.cpu.empty());
  EXPECT_GE(m.cores, 1);
  EXPECT_FALSE(m.blas_kernels.empty()) << "the BLAS in use is not OpenBLAS (libopenblas0-pthread)";
  EXPECT_EQ(m.torch_version.substr(0, 2), "1.");
  // a git describe (hex digits, maybe a tag and -dirty) or "unknown" outside a checkout
  EXPECT_FALSE(m.rlt_commit.empty());
  EXPECT_EQ(machine_difference(m, current_machine()), "");
}

TEST(MachineInfoTest, DifferenceNamesWhatChangesTrajectories) {
  MachineInfo a;
  a.cpu = "Intel Xeon";
  a.cores = 2;
  a.blas_kernels = "SkylakeX";
  a.torch_version = "1.13.0";
  a.rlt_commit = "f7063c2";
  MachineInfo b = a;
  b.cores = 8;  // threads are set per run: the core count alone changes nothing
  EXPECT_EQ(machine_difference(a, b), "");
  b.cpu = "AMD EPYC";
  b.blas_kernels = "Haswell";
  EXPECT_EQ(machine_difference(a, b), "CPU Intel Xeon -> AMD EPYC, BLAS kernels SkylakeX -> Haswell");
  b = a;
  b.rlt_commit = "2562f09-dirty";
  b.blas_kernels = "";
  EXPECT_EQ(machine_difference(a, b), "BLAS kernels SkylakeX -> none, rlt f7063c2 -> 2562f09-dirty");
}

}  // namespace
}  // namespace rlt
