#include <cstdlib>  // defines __GLIBC__ with the GNU C library

#include "apps/x2car/cli.hpp"

#if defined(__GLIBC__)
#include <malloc.h>
#endif

int main(int argc, char** argv) {
#if defined(__GLIBC__)
  // The camera's estimators allocate image-sized buffers (pyramids, warped images) for every frame
  // on every thread. By default glibc serves blocks this large by mmap and hands them back to the
  // kernel when freed (or trims its heap's top), so each frame's buffers are fresh pages that the
  // kernel must map and zero: 6 % of the motion estimator's CPU time in `perf`, 4 % of its wall
  // time. Kept in the heap, the next frame reuses them; the peak memory stays what it was
  // (122 -> 128 MB on a 1242 x 375 drive).
  mallopt(M_MMAP_THRESHOLD, 32 * 1024 * 1024);
  mallopt(M_TRIM_THRESHOLD, 256 * 1024 * 1024);
#endif
  return x2car::cli::run_cli(argc, argv);
}
