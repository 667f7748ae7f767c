/* A planted race for tests/tsan/tsan.sh: tasks created the way psim
 * creates them (a task_spawn_* function, src/engine/task.h) whose bodies
 * add to one counter without synchronisation.  ThreadSanitizer must
 * report it although tests/tsan/tsan.supp is in force: the suppression
 * covers the creating function's write of the task record only. */
#include <stdio.h>

#include "engine/task.h"

static long counter; /* every task adds to it: a real race */

static void body(long k)
{
    counter += k;
}

PSIM_TASK_SPAWN static void task_spawn_bump(long k)
{
#pragma omp task firstprivate(k) default(none)
    body(k);
}

int main(void)
{
#pragma omp parallel num_threads(2)
#pragma omp single
    for (long k = 0; k < 20000; k++)
        task_spawn_bump(k);
    printf("%ld\n", counter);
    return 0;
}
