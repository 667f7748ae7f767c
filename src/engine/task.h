/* Task creation.  Every OpenMP task psim creates is created in a function
 * of its own, named task_spawn_* and never inlined (PSIM_TASK_SPAWN), that
 * does nothing else: the only memory it writes is the new task's record
 * (its firstprivate values and shared pointers).  ThreadSanitizer, told
 * by Archer what OpenMP synchronises, still reports libomp's reuse of a
 * finished task's record (its per-thread pool, a synchronisation inside
 * the uninstrumented runtime) as a race between that write and the
 * finished task's read of its own record; tests/tsan/tsan.supp suppresses
 * exactly the reports one of whose accesses has such a function on top
 * (race_top:task_spawn_), docs/reliability.md. */
#ifndef PSIM_ENGINE_TASK_H
#define PSIM_ENGINE_TASK_H

#define PSIM_TASK_SPAWN __attribute__((noinline))

#endif
