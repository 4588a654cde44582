// levelfuse: the heap's free memory handed back to the system.
#pragma once

namespace levelfuse {

/// Hands the free pages of every heap of the process back to the system.
/// glibc gives each thread a heap of its own (an arena), and memory one
/// thread frees stays with that heap: when a phase lets go of what the worker
/// threads built (a fusion's grids) and the next phase allocates on another
/// thread, the process would hold both. Called where a large structure has
/// just been let go; costs a walk of the heaps' free lists. Does nothing
/// where the C library offers no such call.
void returnFreedMemory();

}  // namespace levelfuse
