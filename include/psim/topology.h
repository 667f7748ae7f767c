/* psim — topology and pinning: which hardware thread each OpenMP thread
 * runs on, planned with hwloc on this machine or on the XML topology of
 * another one. */
#ifndef PSIM_TOPOLOGY_H
#define PSIM_TOPOLOGY_H

#include <stdio.h>

#include "psim/psim.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct psim_topo psim_topo;

/* Load this machine's topology (xml == NULL) or an hwloc XML file. */
PSIM_API psim_topo *psim_topo_load(const char *xml, psim_error *err);
/* Take an already loaded hwloc_topology_t (used by tests that build their
 * own); the psim_topo owns it from then on. */
PSIM_API psim_topo *psim_topo_wrap(void *hwloc_topology, psim_error *err);
PSIM_API void psim_topo_free(psim_topo *t);
/* Whether binding acts on this machine (not on a foreign XML topology). */
PSIM_API int psim_topo_is_this_system(const psim_topo *t);
/* Print the machine: CPU kinds and their infos, cores, PUs, caches, NUMA. */
PSIM_API void psim_topo_print(FILE *f, const psim_topo *t);

typedef enum {
    PSIM_PIN_NONE = 0, /* no binding */
    PSIM_PIN_PCORES,   /* one thread per core of the most efficient kind */
    PSIM_PIN_ECORES,   /* one per core of the least efficient kind */
    PSIM_PIN_CORES,    /* one per physical core of any kind */
    PSIM_PIN_ALL,      /* one per hardware thread */
    PSIM_PIN_NUMA      /* the cores of NUMA node `numa`, or of every NUMA node
                        * (numa -1: ranks then get whole nodes or parts of one) */
} psim_pin_kind;

typedef struct psim_pin_policy {
    psim_pin_kind kind;
    int numa;
} psim_pin_policy;

/* Parse "none", "pcores", "ecores", "cores", "all", "numa" or "numa:K". */
PSIM_API int psim_pin_parse(const char *text, psim_pin_policy *p, psim_error *err);
PSIM_API const char *psim_pin_name(const psim_pin_policy *p, char *buf, size_t len);

/* Where one thread goes. */
typedef struct psim_pin_slot {
    int pu;          /* OS index of the PU (hardware thread) */
    int core;        /* logical index of its core */
    int kind;        /* rank of its CPU kind, 0 = least efficient; -1 unknown */
    int numa;        /* logical index of its NUMA node, -1 unknown */
} psim_pin_slot;

typedef struct psim_pin_plan {
    psim_pin_policy policy;
    int threads;
    int cores;             /* cores the policy covers */
    int pus;               /* PUs of those cores */
    psim_pin_slot *slot;   /* threads entries; NULL for PSIM_PIN_NONE */
    char notice[256];      /* one line for the user, or "" */
    int rank, ranks;       /* the share of rank `rank` of `ranks` (ranks 0:
                            * the plan is the whole policy's) */
    char share[96];        /* that share: "NUMA node 1, cores 2-3" */
} psim_pin_plan;

/* Plan threads (0: one per core of the policy, one per PU for "all") for a
 * policy.  Threads beyond the policy's cores go round-robin over its PUs,
 * second hardware threads of each core first, and the plan's notice says
 * so; on a machine of one CPU kind pcores and ecores mean every core. */
PSIM_API int psim_pin_plan_make(const psim_topo *t, const psim_pin_policy *p,
                                int threads, psim_pin_plan *plan, psim_error *err);
/* Plan rank `rank` of `ranks` ranks on one machine.  The policy's cores
 * (whatever this process's CPU mask) are shared out by whole domains
 * where the ranks fit them: whole NUMA nodes when the ranks divide the
 * NUMA nodes holding those cores; else whole CPU kinds, most efficient
 * first, when they divide the kinds; else, when the NUMA nodes divide the
 * ranks, each node's cores cut into equal blocks; else the cores, in
 * topology order, cut into `ranks` blocks as equal as possible (the first
 * ones one core larger).  "numa" insists on NUMA nodes.  The share is then
 * kept to this process's CPU mask; threads (0: one per core of the share,
 * one per PU with "all") go on it as psim_pin_plan_make places them.
 * Returns 0; 1 when the share lies wholly outside the mask (plan->share
 * names it, plan->cores counts its cores, no slots); -2 when the ranks cannot share the policy's cores
 * (more ranks than cores; "numa" and ranks that fit no NUMA layout); -1 on
 * other errors. */
PSIM_API int psim_pin_plan_rank(const psim_topo *t, const psim_pin_policy *p, int threads,
                                int rank, int ranks, psim_pin_plan *plan, psim_error *err);
PSIM_API void psim_pin_plan_free(psim_pin_plan *plan);
/* Name of CPU kind `kind` ("IntelCore", or "kind1" without a CoreType). */
PSIM_API const char *psim_topo_kind_name(const psim_topo *t, int kind);
/* Rank of the CPU kind of the PU with OS index pu (0 = least efficient),
 * or -1 when unknown. */
PSIM_API int psim_topo_kind_of_pu(const psim_topo *t, int pu);
/* Print the plan as a table: thread, PU, core, CPU kind, NUMA node. */
PSIM_API void psim_pin_plan_print(FILE *f, const psim_topo *t, const psim_pin_plan *plan);
/* Print the plans of `ranks` ranks: each rank's share, then the table
 * with a leading rank column. */
PSIM_API void psim_pin_plans_print(FILE *f, const psim_topo *t, const psim_pin_plan *plans,
                                   int ranks);

/* Bind thread k of every later OpenMP team of plan->threads threads to
 * slot k, and read back where each runs (observed[k], an OS PU index, or
 * -1).  Binding acts only on this system; elsewhere observed is -1. */
PSIM_API int psim_pin_apply(const psim_topo *t, const psim_pin_plan *plan,
                            int *observed, psim_error *err);

/* Memory policy: local (first touch by the working threads, the default)
 * or interleave (pages spread over the NUMA nodes of the plan). */
typedef enum { PSIM_MEM_LOCAL = 0, PSIM_MEM_INTERLEAVE } psim_mem_policy;
PSIM_API int psim_mem_apply(const psim_topo *t, const psim_pin_plan *plan,
                            psim_mem_policy mem, psim_error *err);

#ifdef __cplusplus
}
#endif
#endif
