/* A planted race for tests/tsan/tsan.sh: tasks created the way psim
 * creates them (a task_spawn_* function, src/engine/task.h) whose bodies
 * add to one counter without synchronisation.  ThreadSanitizer must
 * report it although tests/tsan/tsan.supp is in force: the suppression
 * covers the creating function's write of the task record only.
 *
 * The race must not depend on timing.  If one thread ran every task, the
 * bodies would be ordered and there would be nothing to report (CI saw
 * that); if the two writes came at the same instant, TSan could miss
 * them (each checks the shadow of the counter before the other has
 * marked it; seen in 5 of 40 runs).  So the two tasks meet first, then
 * write one after the other.  They signal with relaxed atomics, which
 * give TSan no happens-before edge: the writes stay unordered for it.
 * A task waiting to meet holds its thread, so the other one runs on the
 * second thread. */
#include <stdio.h>
#include <time.h>

#include "engine/task.h"

static long counter; /* both tasks add to it: a real race */
static int arrived;  /* tasks that reached the meeting point */
static int written;  /* the first task has added to the counter */

static void body(long k)
{
    counter += k;
}

/* wait (at most 20 s, so a broken runtime fails instead of hanging)
 * until *flag reaches at least want */
static void await(const int *flag, int want)
{
    struct timespec t0, t;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    while (__atomic_load_n(flag, __ATOMIC_RELAXED) < want) {
        clock_gettime(CLOCK_MONOTONIC, &t);
        if (t.tv_sec - t0.tv_sec > 20) {
            fprintf(stderr, "planted: the other task never came\n");
            return;
        }
    }
}

/* the first task to arrive writes once both are there; the second
 * writes after it */
static void meet_and_write(long k)
{
    int ticket = __atomic_fetch_add(&arrived, 1, __ATOMIC_RELAXED);
    if (ticket == 0) {
        await(&arrived, 2);
        body(k);
        __atomic_store_n(&written, 1, __ATOMIC_RELAXED);
    } else {
        await(&written, 1);
        body(k);
    }
}

PSIM_TASK_SPAWN static void task_spawn_bump(long k)
{
#pragma omp task firstprivate(k) default(none)
    meet_and_write(k);
}

int main(void)
{
#pragma omp parallel num_threads(2)
#pragma omp single
    for (long k = 1; k <= 2; k++)
        task_spawn_bump(k);
    printf("%ld\n", counter);
    return 0;
}
