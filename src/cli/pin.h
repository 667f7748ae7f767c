/* Where a run's threads and memory go (pin.c). */
#ifndef PSIM_CLI_PIN_H
#define PSIM_CLI_PIN_H
#include <stdio.h>

#include "psim/psim.h"
#include "psim/topology.h"

/* Pinning options shared by the run and plan commands. */
enum { CLI_OPT_PIN = 1000, CLI_OPT_TOPOLOGY, CLI_OPT_MEM, CLI_OPT_DRY_RUN, CLI_OPT_RANKS };

typedef struct cli_pin {
    psim_pin_policy policy;
    const char *topology;
    psim_mem_policy mem;
    int dry_run;
    psim_topo *topo;      /* loaded only when the options need it */
    psim_pin_plan plan;
    int *observed;        /* PU each thread was seen on after binding */
    int rank, size;       /* under an MPI launcher (ranked): this rank of size */
    int local_rank, local_size;  /* and of the ranks on this node */
    int ranked;           /* the plan is this rank's share of the node's */
} cli_pin;

int cli_pin_option(cli_pin *p, int opt, const char *arg);
/* Load, plan, set the memory policy and bind; -1 after printing an error,
 * -2 after a usage error (more ranks on this node than the policy's
 * cores).  Under an MPI launcher (cli_launcher_rank) a rank takes its
 * share of the plan for the node's ranks, kept to the CPUs the launcher
 * gave it; where it gave none of them, the rank warns and plans on those
 * CPUs. */
int cli_pin_setup(cli_pin *p, int threads, int quiet);
/* The run summary's placement line: the plan and where each thread ran
 * (with --pin), or where each ran when the OpenMP runtime or likwid-pin
 * placed them. */
void cli_pin_summary(FILE *f, const cli_pin *p, const psim_sim *s);
char *cli_pin_json(const cli_pin *p);  /* malloc'd JSON members */
void cli_pin_free(cli_pin *p);

#endif
