#include "core/common/memory_trim.hpp"

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace luxloc {

void MemoryTrim::trim() {
#if defined(__GLIBC__)
  ::malloc_trim(0);
#endif
}

}  // namespace luxloc
