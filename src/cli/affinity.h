/* The CPUs and OpenMP settings a run starts with (affinity.c). */
#ifndef PSIM_CLI_AFFINITY_H
#define PSIM_CLI_AFFINITY_H

/* The CPUs and OpenMP settings a run starts with (affinity.c, fixed
 * before the OpenMP runtime starts; docs/experiments.md, "Pinning").
 * cli_wait_note: why OMP_WAIT_POLICY=passive was chosen (NULL if it
 * was not: the runtime's default, or the user's own setting).
 * cli_binders_removed: the runtime's binding variables taken out because
 * --pin places the threads ("OMP_PROC_BIND=spread ..."; NULL: none).
 * cli_outside_placement: what places the threads when psim does not
 * (those variables, likwid-pin; NULL: nothing).  cli_with_start_cpus
 * calls fn with the calling thread's mask widened back to the start mask
 * (the runtime may have bound it), then restores it. */
const char *cli_wait_note(void);
const char *cli_binders_removed(void);
const char *cli_outside_placement(void);
int cli_with_start_cpus(int (*fn)(void *), void *ctx);

#endif
