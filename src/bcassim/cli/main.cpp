// bcassim command-line program: hands its arguments to runCli (Cli.cpp).
#include <malloc.h>

#include "bcassim/cli/Cli.h"

int main(int argc, char** argv) {
  // Large blocks from the heap, and freed ones kept for reuse, instead of a fresh mmap each time:
  // a full-state UKF allocates n x n and n x S temporaries of ~62 MB every step, and on this
  // project's VMs first-touching such a block costs ~100 ms of page faults against ~10 ms for a
  // reused one (docs/benchmarks.md §5). glibc's defaults mmap blocks over 32 MB.
  mallopt(M_MMAP_THRESHOLD, 1 << 30);
  mallopt(M_TRIM_THRESHOLD, 1 << 30);
  return bcassim::runCli(argc, argv);
}
