#include "core/common/memory_trim.hpp"

#include <cstdlib>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace luxloc {

void use_one_heap_arena() {
#if defined(__GLIBC__)
  if (std::getenv("MALLOC_ARENA_MAX") == nullptr) ::mallopt(M_ARENA_MAX, 1);
#endif
}

void MemoryTrim::trim() {
#if defined(__GLIBC__)
  ::malloc_trim(0);
#endif
}

}  // namespace luxloc
