/* include/psim/topology.h in a build without hwloc (-DPSIM_HWLOC=OFF):
 * no topology loads, so nothing pins; runs that do not pin (the default,
 * --pin none) are as in any build.  For machines without hwloc's library
 * (bench/gpu_check.sh builds so). */
#include <stdlib.h>
#include <string.h>

#include "psim/topology.h"
#include "base/error.h"

#define NO_HWLOC "psim was built without hwloc (-DPSIM_HWLOC=OFF): no topology, no pinning"

psim_topo *psim_topo_load(const char *xml, psim_error *err)
{
    (void)xml;
    psim_error_set(err, NO_HWLOC);
    return NULL;
}

psim_topo *psim_topo_wrap(void *hwloc_topology, psim_error *err)
{
    (void)hwloc_topology;
    psim_error_set(err, NO_HWLOC);
    return NULL;
}

void psim_topo_free(psim_topo *t) { (void)t; }
int psim_topo_is_this_system(const psim_topo *t) { (void)t; return 0; }
void psim_topo_print(FILE *f, const psim_topo *t) { (void)f, (void)t; }

int psim_pin_parse(const char *text, psim_pin_policy *p, psim_error *err)
{
    if (!strcmp(text, "none")) {
        *p = (psim_pin_policy){PSIM_PIN_NONE, -1};
        return 0;
    }
    psim_error_set(err, NO_HWLOC);
    return -1;
}

const char *psim_pin_name(const psim_pin_policy *p, char *buf, size_t len)
{
    (void)p;
    snprintf(buf, len, "none");
    return buf;
}

int psim_pin_plan_make(const psim_topo *t, const psim_pin_policy *p, int threads,
                       psim_pin_plan *plan, psim_error *err)
{
    (void)t, (void)p, (void)threads, (void)plan;
    psim_error_set(err, NO_HWLOC);
    return -1;
}

int psim_pin_plan_rank(const psim_topo *t, const psim_pin_policy *p, int threads, int rank,
                       int ranks, psim_pin_plan *plan, psim_error *err)
{
    (void)rank, (void)ranks;
    return psim_pin_plan_make(t, p, threads, plan, err);
}

void psim_pin_plan_free(psim_pin_plan *plan)
{
    free(plan->slot);
    plan->slot = NULL;
}

const char *psim_topo_kind_name(const psim_topo *t, int kind)
{
    (void)t, (void)kind;
    return "unknown";
}

int psim_topo_kind_of_pu(const psim_topo *t, int pu)
{
    (void)t, (void)pu;
    return -1;
}

void psim_pin_plan_print(FILE *f, const psim_topo *t, const psim_pin_plan *plan)
{
    (void)f, (void)t, (void)plan;
}

void psim_pin_plans_print(FILE *f, const psim_topo *t, const psim_pin_plan *plans, int ranks)
{
    (void)f, (void)t, (void)plans, (void)ranks;
}

int psim_pin_apply(const psim_topo *t, const psim_pin_plan *plan, int *observed,
                   psim_error *err)
{
    (void)t, (void)plan, (void)observed;
    psim_error_set(err, NO_HWLOC);
    return -1;
}

int psim_mem_apply(const psim_topo *t, const psim_pin_plan *plan, psim_mem_policy mem,
                   psim_error *err)
{
    (void)t, (void)plan, (void)mem;
    psim_error_set(err, NO_HWLOC);
    return -1;
}
