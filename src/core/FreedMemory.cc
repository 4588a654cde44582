// levelfuse: the heap's free memory handed back to the system.

#include <levelfuse/core/FreedMemory.h>

#include <cstdlib>  // defines __GLIBC__ with the GNU C library

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace levelfuse {

void returnFreedMemory() {
#if defined(__GLIBC__)
  malloc_trim(0);
#endif
}

}  // namespace levelfuse
