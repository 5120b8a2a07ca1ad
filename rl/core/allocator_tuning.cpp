#include "rl/core/allocator_tuning.h"

#include <malloc.h>

namespace rlt {

void tune_allocator_for_training() {
#ifdef __GLIBC__
  mallopt(M_MMAP_THRESHOLD, 256 << 20);
  mallopt(M_TRIM_THRESHOLD, 256 << 20);
  mallopt(M_TOP_PAD, 64 << 20);
#endif
}

}  // namespace rlt
