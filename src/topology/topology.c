/* Topology and pinning with hwloc (see include/psim/topology.h). */
#include "psim/topology.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <hwloc.h>
#include <omp.h>

#include "base/error.h"

#define MAX_KINDS 16

struct psim_topo {
    hwloc_topology_t h;
    hwloc_obj_type_t core_type;  /* CORE, or PU where a topology has no cores */
    int ncores;
    int nkinds;                  /* ranked kinds; 1 when there is one or none */
    int *core_kind;              /* per core: rank of its kind */
    char kind_name[MAX_KINDS][48];
    char kinds_error[256];       /* unranked kinds we cannot tell apart */
    hwloc_bitmap_t allowed;      /* this process's CPU mask (taskset, cpuset
                                  * cgroup); NULL: every PU (a foreign XML) */
    int allowed_cores;           /* cores with a PU in it */
};

/* ---- loading and CPU kinds --------------------------------------------- */

static const char *info(const struct hwloc_info_s *infos, unsigned n,
                        const char *name)
{
    for (unsigned k = 0; k < n; k++)
        if (strcmp(infos[k].name, name) == 0)
            return infos[k].value;
    return NULL;
}

/* A score that orders kinds by power when hwloc could not rank them:
 * CoreType first (IntelAtom < IntelCore), then maximum or base frequency.
 * Returns -1 when the infos say nothing usable. */
static double kind_score(const struct hwloc_info_s *infos, unsigned n)
{
    const char *type = info(infos, n, "CoreType");
    if (type && strcmp(type, "IntelAtom") == 0)
        return 1e9;
    if (type && strcmp(type, "IntelCore") == 0)
        return 2e9;
    const char *f = info(infos, n, "FrequencyMaxMHz");
    if (!f)
        f = info(infos, n, "FrequencyBaseMHz");
    return f ? atof(f) : -1;
}

static void rank_kinds(psim_topo *t)
{
    int nr = hwloc_cpukinds_get_nr(t->h, 0);
    t->nkinds = 1;
    for (int c = 0; c < t->ncores; c++)
        t->core_kind[c] = 0;
    snprintf(t->kind_name[0], sizeof t->kind_name[0], "any");
    if (nr <= 0)
        return;
    if (nr > MAX_KINDS)
        nr = MAX_KINDS;
    hwloc_bitmap_t set[MAX_KINDS];
    double score[MAX_KINDS];
    int eff[MAX_KINDS], rank[MAX_KINDS], unranked = 0;
    for (int k = 0; k < nr; k++) {
        unsigned ninfo = 0;
        struct hwloc_info_s *infos = NULL;
        set[k] = hwloc_bitmap_alloc();
        hwloc_cpukinds_get_info(t->h, (unsigned)k, set[k], &eff[k], &ninfo, &infos, 0);
        score[k] = kind_score(infos, ninfo);
        unranked |= eff[k] < 0;
        const char *type = info(infos, ninfo, "CoreType");
        snprintf(t->kind_name[k], sizeof t->kind_name[k], "%s", type ? type : "");
    }
    /* hwloc lists ranked kinds from least to most efficient; unranked ones
     * are ordered here by score, and must all differ */
    for (int k = 0; k < nr; k++) {
        rank[k] = 0;
        for (int o = 0; o < nr; o++)
            if (unranked ? score[o] < score[k] : o < k)
                rank[k]++;
    }
    if (unranked)
        for (int k = 0; k < nr; k++)
            for (int o = k + 1; o < nr; o++)
                if (score[k] < 0 || score[o] < 0 || score[k] == score[o])
                    snprintf(t->kinds_error, sizeof t->kinds_error,
                             "the %d CPU kinds are unranked (efficiency -1) and their "
                             "CoreType and frequency infos do not tell them apart", nr);
    char names[MAX_KINDS][48];
    for (int k = 0; k < nr; k++)
        snprintf(names[rank[k]], sizeof names[0], "%s", t->kind_name[k]);
    for (int k = 0; k < nr; k++) {
        if (!names[k][0])
            snprintf(names[k], sizeof names[0], "kind%d", k);
        for (char *c = names[k]; *c; c++) /* names go into tables and JSON */
            if (*c == '"' || *c == '\\' || *c < 0x21 || *c > 0x7e)
                *c = '_';
        memcpy(t->kind_name[k], names[k], sizeof t->kind_name[k]);
    }
    t->nkinds = nr;
    for (int c = 0; c < t->ncores; c++) {
        hwloc_obj_t core = hwloc_get_obj_by_type(t->h, t->core_type, (unsigned)c);
        t->core_kind[c] = -1;
        for (int k = 0; k < nr; k++)
            if (hwloc_bitmap_intersects(core->cpuset, set[k]))
                t->core_kind[c] = rank[k];
    }
    for (int k = 0; k < nr; k++)
        hwloc_bitmap_free(set[k]);
}

/* The CPUs this process may run on, as hwloc-bind and likwid-pin respect
 * them: a plan never leaves the mask `taskset` or a cpuset gave psim.  On a
 * foreign topology (XML) there is no such mask. */
static void allowed_cpus(psim_topo *t)
{
    t->allowed = NULL;
    t->allowed_cores = t->ncores;
    if (!hwloc_topology_is_thissystem(t->h))
        return;
    hwloc_bitmap_t set = hwloc_bitmap_alloc();
    if (!set || hwloc_get_cpubind(t->h, set, HWLOC_CPUBIND_PROCESS) != 0 ||
        hwloc_bitmap_iszero(set)) {
        hwloc_bitmap_free(set);
        return;
    }
    t->allowed = set;
    t->allowed_cores = 0;
    for (int c = 0; c < t->ncores; c++) {
        hwloc_obj_t core = hwloc_get_obj_by_type(t->h, t->core_type, (unsigned)c);
        t->allowed_cores += hwloc_bitmap_intersects(core->cpuset, set);
    }
}

/* Whether PU pu may be used (in the process's mask). */
static int pu_allowed(const psim_topo *t, int pu)
{
    return !t->allowed || hwloc_bitmap_isset(t->allowed, (unsigned)pu);
}

psim_topo *psim_topo_wrap(void *hwloc_topology, psim_error *err)
{
    psim_topo *t = calloc(1, sizeof *t);
    if (!t) {
        hwloc_topology_destroy((hwloc_topology_t)hwloc_topology);
        psim_error_set(err, "out of memory");
        return NULL;
    }
    t->h = (hwloc_topology_t)hwloc_topology;
    t->core_type = HWLOC_OBJ_CORE;
    t->ncores = hwloc_get_nbobjs_by_type(t->h, HWLOC_OBJ_CORE);
    if (t->ncores <= 0) {
        t->core_type = HWLOC_OBJ_PU;
        t->ncores = hwloc_get_nbobjs_by_type(t->h, HWLOC_OBJ_PU);
    }
    t->core_kind = calloc((size_t)(t->ncores > 0 ? t->ncores : 1), sizeof *t->core_kind);
    if (!t->core_kind) {
        psim_topo_free(t);
        psim_error_set(err, "out of memory");
        return NULL;
    }
    rank_kinds(t);
    allowed_cpus(t);
    return t;
}

psim_topo *psim_topo_load(const char *xml, psim_error *err)
{
    hwloc_topology_t h;
    if (hwloc_topology_init(&h)) {
        psim_error_set(err, "hwloc: cannot initialise a topology");
        return NULL;
    }
    if (xml && access(xml, R_OK) != 0) {
        psim_error_set(err, "%s: cannot read: %s", xml, strerror(errno));
        hwloc_topology_destroy(h);
        return NULL;
    }
    if ((xml && hwloc_topology_set_xml(h, xml) != 0) || hwloc_topology_load(h) != 0) {
        psim_error_set(err, "%s: not a topology hwloc can load", xml ? xml : "this machine");
        hwloc_topology_destroy(h);
        return NULL;
    }
    return psim_topo_wrap(h, err);
}

void psim_topo_free(psim_topo *t)
{
    if (!t)
        return;
    if (t->h)
        hwloc_topology_destroy(t->h);
    if (t->allowed)
        hwloc_bitmap_free(t->allowed);
    free(t->core_kind);
    free(t);
}

int psim_topo_is_this_system(const psim_topo *t)
{
    return hwloc_topology_is_thissystem(t->h);
}

const char *psim_topo_kind_name(const psim_topo *t, int kind)
{
    if (kind < 0 || kind >= t->nkinds)
        return "?";
    return t->kind_name[kind];
}

int psim_topo_kind_of_pu(const psim_topo *t, int pu)
{
    if (pu < 0)
        return -1;
    for (int c = 0; c < t->ncores; c++) {
        hwloc_obj_t core = hwloc_get_obj_by_type(t->h, t->core_type, (unsigned)c);
        if (hwloc_bitmap_isset(core->cpuset, (unsigned)pu))
            return t->nkinds > 1 ? t->core_kind[c] : 0;
    }
    return -1;
}

/* ---- policies and plans -------------------------------------------------- */

int psim_pin_parse(const char *s, psim_pin_policy *p, psim_error *err)
{
    static const struct { const char *name; psim_pin_kind kind; } names[] = {
        {"none", PSIM_PIN_NONE}, {"pcores", PSIM_PIN_PCORES}, {"ecores", PSIM_PIN_ECORES},
        {"cores", PSIM_PIN_CORES}, {"all", PSIM_PIN_ALL}};
    p->numa = -1;
    for (size_t k = 0; k < sizeof names / sizeof names[0]; k++)
        if (strcmp(s, names[k].name) == 0) {
            p->kind = names[k].kind;
            return 0;
        }
    if (strcmp(s, "numa") == 0) {
        p->kind = PSIM_PIN_NUMA;
        return 0;
    }
    if (strncmp(s, "numa:", 5) == 0) {
        char *end;
        long v = strtol(s + 5, &end, 10);
        if (end != s + 5 && !*end && v >= 0 && v < 1 << 20) {
            p->kind = PSIM_PIN_NUMA;
            p->numa = (int)v;
            return 0;
        }
    }
    psim_error_set(err, "--pin: unknown policy '%s' (pcores, ecores, cores, all, "
                        "numa, numa:K, none)", s);
    return -1;
}

const char *psim_pin_name(const psim_pin_policy *p, char *buf, size_t len)
{
    static const char *names[] = {"none", "pcores", "ecores", "cores", "all", "numa"};
    if (p->kind == PSIM_PIN_NUMA && p->numa >= 0)
        snprintf(buf, len, "numa:%d", p->numa);
    else
        snprintf(buf, len, "%s", names[p->kind]);
    return buf;
}

static int numa_of_pu(hwloc_topology_t h, unsigned pu)
{
    int n = hwloc_get_nbobjs_by_type(h, HWLOC_OBJ_NUMANODE);
    for (int k = 0; k < n; k++) {
        hwloc_obj_t node = hwloc_get_obj_by_type(h, HWLOC_OBJ_NUMANODE, (unsigned)k);
        if (node->cpuset && hwloc_bitmap_isset(node->cpuset, pu))
            return k;
    }
    return -1;
}

static int numa_of_core(const psim_topo *t, int c)
{
    hwloc_obj_t core = hwloc_get_obj_by_type(t->h, t->core_type, (unsigned)c);
    int pu = hwloc_bitmap_first(core->cpuset);
    return pu < 0 ? -1 : numa_of_pu(t->h, (unsigned)pu);
}

/* Which cores a policy covers: sel[c] = 1, within this process's CPU mask
 * when masked. Returns their number or -1. */
static int select_cores(const psim_topo *t, const psim_pin_policy *p, char *sel,
                        char *notice, size_t nlen, int masked, psim_error *err)
{
    char name[32];
    psim_pin_name(p, name, sizeof name);
    hwloc_obj_t node = NULL;
    if (p->kind == PSIM_PIN_NUMA && p->numa >= 0) {
        int nodes = hwloc_get_nbobjs_by_type(t->h, HWLOC_OBJ_NUMANODE);
        node = hwloc_get_obj_by_type(t->h, HWLOC_OBJ_NUMANODE, (unsigned)p->numa);
        if (!node) {
            psim_error_set(err, "--pin=%s: this machine has %d NUMA node%s (0..%d)",
                           name, nodes, nodes == 1 ? "" : "s", nodes - 1);
            return -1;
        }
    }
    int kindwise = p->kind == PSIM_PIN_PCORES || p->kind == PSIM_PIN_ECORES;
    if (kindwise && t->nkinds > 1 && t->kinds_error[0]) {
        psim_error_set(err, "--pin=%s: %s; use --pin=cores or --pin=all", name,
                       t->kinds_error);
        return -1;
    }
    if (kindwise && t->nkinds <= 1)
        snprintf(notice, nlen, "one CPU kind on this machine: --pin=%s uses every core", name);
    int want = p->kind == PSIM_PIN_PCORES ? t->nkinds - 1 : 0, count = 0, cut = 0;
    for (int c = 0; c < t->ncores; c++) {
        hwloc_obj_t core = hwloc_get_obj_by_type(t->h, t->core_type, (unsigned)c);
        int in = 1;
        if (kindwise && t->nkinds > 1)
            in = t->core_kind[c] == want;
        if (node)
            in = node->cpuset && hwloc_bitmap_intersects(core->cpuset, node->cpuset);
        else if (p->kind == PSIM_PIN_NUMA)
            in = numa_of_core(t, c) >= 0;
        int ok = !masked || !t->allowed || hwloc_bitmap_intersects(core->cpuset, t->allowed);
        cut += in && !ok;
        in = in && ok;
        sel[c] = (char)in;
        count += in;
    }
    if (count == 0) {
        if (cut)
            psim_error_set(err, "--pin=%s: none of its %d cores is in this process's CPU mask "
                                "(taskset or cpuset: %d of %d cores allowed)",
                           name, cut, t->allowed_cores, t->ncores);
        else
            psim_error_set(err, "--pin=%s: no cores match on this machine", name);
        return -1;
    }
    if (cut)
        snprintf(notice, nlen, "--pin=%s: left out %d of its %d cores, outside this process's "
                               "CPU mask (taskset or cpuset)",
                 name, cut, count + cut);
    return count;
}

/* The plan's slots on the chosen cores sel (plan->cores of them). */
static int plan_slots(const psim_topo *t, const psim_pin_policy *p, const char *sel,
                      int threads, psim_pin_plan *plan, psim_error *err)
{
    psim_pin_slot *slots = NULL;
    int rc = -1;
    /* slots: the first PU of every chosen core, then their second PUs, ... */
    int npu_max = hwloc_get_nbobjs_by_type(t->h, HWLOC_OBJ_PU);
    slots = calloc((size_t)npu_max + 1, sizeof *slots);
    if (!slots)
        goto oom;
    int n = 0;
    for (int r = 0; n < npu_max; r++) {
        int added = 0;
        for (int c = 0; c < t->ncores; c++) {
            if (!sel[c])
                continue;
            hwloc_obj_t core = hwloc_get_obj_by_type(t->h, t->core_type, (unsigned)c);
            int pu = hwloc_bitmap_first(core->cpuset);   /* its r-th allowed PU */
            while (pu >= 0 && !pu_allowed(t, pu))
                pu = hwloc_bitmap_next(core->cpuset, pu);
            for (int k = 0; k < r && pu >= 0; k++)
                do
                    pu = hwloc_bitmap_next(core->cpuset, pu);
                while (pu >= 0 && !pu_allowed(t, pu));
            if (pu < 0)
                continue;
            slots[n++] = (psim_pin_slot){pu, c, t->nkinds > 1 ? t->core_kind[c] : 0,
                                         numa_of_pu(t->h, (unsigned)pu)};
            added++;
        }
        if (!added)
            break;
    }
    plan->pus = n;
    int room = p->kind == PSIM_PIN_ALL ? plan->pus : plan->cores;
    if (threads <= 0)
        threads = room;
    plan->threads = threads;
    if (threads > room) {
        char name[32];
        snprintf(plan->notice, sizeof plan->notice,
                 "%d threads on %d %s of --pin=%s: oversubscribed, placed round-robin "
                 "over its %d hardware threads", threads, room,
                 p->kind == PSIM_PIN_ALL ? "hardware threads" : "cores",
                 psim_pin_name(p, name, sizeof name), plan->pus);
    }
    plan->slot = calloc((size_t)threads, sizeof *plan->slot);
    if (!plan->slot)
        goto oom;
    for (int k = 0; k < threads; k++)
        plan->slot[k] = slots[k % plan->pus];
    rc = 0;
    goto done;
oom:
    psim_error_set(err, "out of memory");
done:
    free(slots);
    return rc;
}

int psim_pin_plan_make(const psim_topo *t, const psim_pin_policy *p,
                       int threads, psim_pin_plan *plan, psim_error *err)
{
    memset(plan, 0, sizeof *plan);
    plan->policy = *p;
    plan->threads = threads;
    if (p->kind == PSIM_PIN_NONE)
        return 0;
    char *sel = calloc((size_t)t->ncores + 1, 1);
    if (!sel) {
        psim_error_set(err, "out of memory");
        return -1;
    }
    plan->cores = select_cores(t, p, sel, plan->notice, sizeof plan->notice, 1, err);
    int rc = plan->cores < 0 ? -1 : plan_slots(t, p, sel, threads, plan, err);
    free(sel);
    return rc;
}

/* ---- ranks' shares ------------------------------------------------------- */

/* Which of `parts` near-equal blocks of m items item i falls in (the first
 * m % parts blocks one larger). */
static int block_of(int i, int m, int parts)
{
    int q = m / parts, r = m % parts;
    return i < r * (q + 1) ? i / (q + 1) : r + (i - r * (q + 1)) / q;
}

/* The domains of the chosen cores: dom[c] for each, and how many distinct
 * ones (numbered 0.. in the order ranks take them); -1 when some chosen
 * core has none.  NUMA nodes go in topology order, CPU kinds from the
 * most efficient. */
static int domains(const psim_topo *t, const char *sel, int by_kind, int *dom)
{
    int n = by_kind ? t->nkinds : hwloc_get_nbobjs_by_type(t->h, HWLOC_OBJ_NUMANODE);
    char *seen = calloc((size_t)(n > 0 ? n : 1), 1);
    int *num = calloc((size_t)(n > 0 ? n : 1), sizeof *num), count = 0, bad = !seen || !num;
    for (int c = 0; c < t->ncores && !bad; c++) {
        if (!sel[c])
            continue;
        int d = by_kind ? t->nkinds - 1 - t->core_kind[c] : numa_of_core(t, c);
        bad = d < 0 || d >= n;
        if (!bad)
            seen[d] = 1, dom[c] = d;
    }
    for (int d = 0; d < n && !bad; d++)
        num[d] = seen[d] ? count++ : -1;
    for (int c = 0; c < t->ncores && !bad; c++)
        if (sel[c])
            dom[c] = num[dom[c]];
    free(seen);
    free(num);
    return bad ? -1 : count;
}

/* Keep in sel the cores whose domain is in [first, first + len) and, of
 * those, block `sub` of `parts`.  Cores outside any domain: dom NULL. */
static void keep(const psim_topo *t, char *sel, const int *dom, int first, int len,
                 int sub, int parts)
{
    int m = 0, i = 0;
    for (int c = 0; c < t->ncores; c++)
        m += sel[c] && (!dom || (dom[c] >= first && dom[c] < first + len));
    for (int c = 0; c < t->ncores; c++) {
        if (!sel[c])
            continue;
        int in = !dom || (dom[c] >= first && dom[c] < first + len);
        sel[c] = (char)(in && block_of(i, m, parts) == sub);
        i += in;
    }
}

/* "NUMA node 1", "NUMA nodes 0-3" or "IntelCore", from the first core
 * kept. */
static void name_domain(const psim_topo *t, const char *sel, int by_kind, int len,
                        char *buf, size_t blen)
{
    int c = 0;
    while (c < t->ncores && !sel[c])
        c++;
    if (by_kind) {
        snprintf(buf, blen, "%s", psim_topo_kind_name(t, t->core_kind[c]));
        for (int o = c + 1; o < t->ncores; o++)
            if (sel[o] && t->core_kind[o] != t->core_kind[c]) {
                snprintf(buf, blen, "%d CPU kinds", len);
                break;
            }
        return;
    }
    int last = c;
    for (int o = c; o < t->ncores; o++)
        if (sel[o])
            last = o;
    int a = numa_of_core(t, c), b = numa_of_core(t, last);
    if (a == b)
        snprintf(buf, blen, "NUMA node %d", a);
    else
        snprintf(buf, blen, "NUMA nodes %d-%d", a, b);
}

/* Cut the policy's cores sel (n of them) down to rank's share and name it
 * in share ("" for plain blocks).  Returns 0, or -2 with err set. */
static int share_cores(const psim_topo *t, const psim_pin_policy *p, char *sel, int n,
                       int rank, int ranks, int *dom, char *share, size_t slen,
                       psim_error *err)
{
    char name[32];
    psim_pin_name(p, name, sizeof name);
    if (ranks > n) {
        psim_error_set(err, "%d ranks on this machine: more than the %d cores of --pin=%s",
                       ranks, n, name);
        return -2;
    }
    int nodes = domains(t, sel, 0, dom), by_kind = 0, len = 0;
    if (nodes > 0 && nodes % ranks == 0) {
        len = nodes / ranks;
        keep(t, sel, dom, rank * len, len, 0, 1);
    } else if (p->kind != PSIM_PIN_NUMA && t->nkinds > 1 &&
               (len = domains(t, sel, 1, dom)) > 1 && len % ranks == 0) {
        by_kind = 1;
        len /= ranks;
        keep(t, sel, dom, rank * len, len, 0, 1);
    } else if (nodes > 1 && ranks % nodes == 0) {
        domains(t, sel, 0, dom);
        int per = ranks / nodes;
        len = 1;
        keep(t, sel, dom, rank / per, 1, rank % per, per);
    } else if (p->kind == PSIM_PIN_NUMA) {
        psim_error_set(err, "--pin=numa: %d ranks fit neither whole nor equal parts of the "
                            "%d NUMA nodes", ranks, nodes);
        return -2;
    } else {
        keep(t, sel, NULL, 0, 0, rank, ranks);
        share[0] = 0;
        return 0;
    }
    name_domain(t, sel, by_kind, len, share, slen);
    return 0;
}

/* Append ", cores 2-3" (or "cores 2-3" to an empty share). */
static void name_cores(const psim_topo *t, const char *sel, char *share, size_t slen)
{
    hwloc_bitmap_t set = hwloc_bitmap_alloc();
    char list[64] = "?";
    for (int c = 0; c < t->ncores && set; c++)
        if (sel[c])
            hwloc_bitmap_set(set, (unsigned)c);
    if (set)
        hwloc_bitmap_list_snprintf(list, sizeof list, set);
    hwloc_bitmap_free(set);
    size_t used = strlen(share);
    snprintf(share + used, slen - used, "%score%s %s", used ? ", " : "",
             strpbrk(list, ",-") ? "s" : "", list);
}

/* Keep sel to this process's CPU mask; returns the cores left. */
static int mask_cores(const psim_topo *t, char *sel)
{
    int count = 0;
    for (int c = 0; c < t->ncores; c++) {
        hwloc_obj_t core = hwloc_get_obj_by_type(t->h, t->core_type, (unsigned)c);
        sel[c] = (char)(sel[c] &&
                        (!t->allowed || hwloc_bitmap_intersects(core->cpuset, t->allowed)));
        count += sel[c];
    }
    return count;
}

int psim_pin_plan_rank(const psim_topo *t, const psim_pin_policy *p, int threads,
                       int rank, int ranks, psim_pin_plan *plan, psim_error *err)
{
    memset(plan, 0, sizeof *plan);
    plan->policy = *p;
    plan->threads = threads;
    plan->rank = rank;
    plan->ranks = ranks;
    if (p->kind == PSIM_PIN_NONE)
        return 0;
    char *sel = calloc((size_t)t->ncores + 1, 1);
    int *dom = calloc((size_t)t->ncores + 1, sizeof *dom);
    int rc = -1;
    if (!sel || !dom)
        psim_error_set(err, "out of memory");
    int n = sel && dom ? select_cores(t, p, sel, plan->notice, sizeof plan->notice, 0, err)
                       : -1;
    if (n >= 0)
        rc = share_cores(t, p, sel, n, rank, ranks, dom, plan->share, sizeof plan->share,
                         err);
    if (rc == 0) {
        name_cores(t, sel, plan->share, sizeof plan->share);
        int whole = 0;
        for (int c = 0; c < t->ncores; c++)
            whole += sel[c];
        int kept = mask_cores(t, sel);
        plan->cores = kept ? kept : whole; /* none in the mask: the share's */
        if (kept && kept < whole)
            snprintf(plan->notice, sizeof plan->notice,
                     "rank %d of %d: left out %d of the %d cores of its share (%s), outside "
                     "this process's CPU mask", rank, ranks, whole - kept, whole, plan->share);
        rc = kept ? plan_slots(t, p, sel, threads, plan, err) : 1;
    }
    free(sel);
    free(dom);
    return rc;
}

void psim_pin_plan_free(psim_pin_plan *plan)
{
    free(plan->slot);
    plan->slot = NULL;
}

/* ---- binding --------------------------------------------------------------- */

int psim_pin_apply(const psim_topo *t, const psim_pin_plan *plan, int *observed,
                   psim_error *err)
{
    for (int k = 0; k < plan->threads; k++)
        observed[k] = -1;
    if (!plan->slot || !psim_topo_is_this_system(t))
        return 0;
    int failed_thread = -1, failed_errno = 0;
#pragma omp parallel num_threads(plan->threads)
    {
        int k = omp_get_thread_num();
        hwloc_bitmap_t set = hwloc_bitmap_alloc();
        hwloc_bitmap_only(set, (unsigned)plan->slot[k].pu);
        if (hwloc_set_cpubind(t->h, set, HWLOC_CPUBIND_THREAD) != 0) {
#pragma omp critical(psim_pin)
            if (failed_thread < 0) {
                failed_thread = k;
                failed_errno = errno;
            }
        } else if (hwloc_get_last_cpu_location(t->h, set, HWLOC_CPUBIND_THREAD) == 0) {
            observed[k] = hwloc_bitmap_first(set);
        }
        hwloc_bitmap_free(set);
    }
    if (failed_thread >= 0) {
        psim_error_set(err, "--pin: cannot bind thread %d to PU %d: %s", failed_thread,
                       plan->slot[failed_thread].pu, strerror(failed_errno));
        return -1;
    }
    return 0;
}

int psim_mem_apply(const psim_topo *t, const psim_pin_plan *plan,
                   psim_mem_policy mem, psim_error *err)
{
    if (mem == PSIM_MEM_LOCAL || !psim_topo_is_this_system(t))
        return 0;
    hwloc_bitmap_t nodes = hwloc_bitmap_alloc();
    int n = hwloc_get_nbobjs_by_type(t->h, HWLOC_OBJ_NUMANODE);
    for (int k = 0; k < n; k++) {
        hwloc_obj_t node = hwloc_get_obj_by_type(t->h, HWLOC_OBJ_NUMANODE, (unsigned)k);
        int used = !plan->slot;
        for (int s = 0; s < plan->threads && plan->slot; s++)
            used |= plan->slot[s].numa == k;
        if (used)
            hwloc_bitmap_or(nodes, nodes, node->nodeset);
    }
    int rc = hwloc_set_membind(t->h, nodes, HWLOC_MEMBIND_INTERLEAVE,
                               HWLOC_MEMBIND_PROCESS | HWLOC_MEMBIND_BYNODESET);
    hwloc_bitmap_free(nodes);
    if (rc != 0 && n > 1) {
        psim_error_set(err, "--mem=interleave: cannot set the memory policy: %s",
                       strerror(errno));
        return -1;
    }
    return 0;
}

/* ---- printing ---------------------------------------------------------------- */

void psim_pin_plan_print(FILE *f, const psim_topo *t, const psim_pin_plan *plan)
{
    char name[32];
    psim_pin_name(&plan->policy, name, sizeof name);
    if (!plan->slot) {
        fprintf(f, "--pin=%s: %d threads, not bound (the OS places them)\n", name,
                plan->threads);
        return;
    }
    fprintf(f, "--pin=%s: %d threads on %d cores (%d hardware threads)%s\n", name,
            plan->threads, plan->cores, plan->pus,
            psim_topo_is_this_system(t) ? "" : ", planned on a foreign topology: not bound");
    fprintf(f, "%6s %5s %5s %-12s %5s\n", "thread", "PU", "core", "CPU kind", "NUMA");
    for (int k = 0; k < plan->threads; k++) {
        const psim_pin_slot *s = &plan->slot[k];
        char numa[16];
        snprintf(numa, sizeof numa, "%d", s->numa);
        fprintf(f, "%6d %5d %5d %-12s %5s\n", k, s->pu, s->core,
                psim_topo_kind_name(t, s->kind), s->numa < 0 ? "-" : numa);
    }
}

void psim_pin_plans_print(FILE *f, const psim_topo *t, const psim_pin_plan *plans,
                          int ranks)
{
    char name[32];
    int threads = 0, cores = 0, pus = 0;
    for (int r = 0; r < ranks; r++)
        threads += plans[r].threads, cores += plans[r].cores, pus += plans[r].pus;
    fprintf(f, "--pin=%s: %d ranks, %d threads on %d cores (%d hardware threads)%s\n",
            psim_pin_name(&plans[0].policy, name, sizeof name), ranks, threads, cores, pus,
            psim_topo_is_this_system(t) ? "" : ", planned on a foreign topology: not bound");
    for (int r = 0; r < ranks; r++)
        fprintf(f, "rank %d: %s, %d thread%s\n", r, plans[r].share, plans[r].threads,
                plans[r].threads == 1 ? "" : "s");
    fprintf(f, "%5s %6s %5s %5s %-12s %5s\n", "rank", "thread", "PU", "core", "CPU kind",
            "NUMA");
    for (int r = 0; r < ranks; r++)
        for (int k = 0; k < plans[r].threads; k++) {
            const psim_pin_slot *s = &plans[r].slot[k];
            char numa[16];
            snprintf(numa, sizeof numa, "%d", s->numa);
            fprintf(f, "%5d %6d %5d %5d %-12s %5s\n", r, k, s->pu, s->core,
                    psim_topo_kind_name(t, s->kind), s->numa < 0 ? "-" : numa);
        }
}

static void print_list(FILE *f, hwloc_const_bitmap_t set)
{
    char *s = NULL;
    if (hwloc_bitmap_iszero(set)) {
        fputs("none", f);
        return;
    }
    hwloc_bitmap_list_asprintf(&s, set);
    fputs(s ? s : "?", f);
    free(s);
}

void psim_topo_print(FILE *f, const psim_topo *t)
{
    hwloc_topology_t h = t->h;
    int pkgs = hwloc_get_nbobjs_by_type(h, HWLOC_OBJ_PACKAGE);
    int pus = hwloc_get_nbobjs_by_type(h, HWLOC_OBJ_PU);
    int nodes = hwloc_get_nbobjs_by_type(h, HWLOC_OBJ_NUMANODE);
    fprintf(f, "machine: %d package%s, %d cores, %d hardware threads (PUs), %d NUMA node%s%s\n",
            pkgs, pkgs == 1 ? "" : "s", t->ncores, pus, nodes, nodes == 1 ? "" : "s",
            hwloc_topology_is_thissystem(h) ? "" : " (not this machine)");
    int nr = hwloc_cpukinds_get_nr(h, 0);
    fprintf(f, "CPU kinds: %d%s\n", nr > 0 ? nr : 1,
            nr > 0 ? " (from least to most efficient)" : " (no kind information)");
    for (int k = 0; k < nr; k++) {
        hwloc_bitmap_t set = hwloc_bitmap_alloc();
        int eff;
        unsigned ninfo = 0;
        struct hwloc_info_s *infos = NULL;
        hwloc_cpukinds_get_info(h, (unsigned)k, set, &eff, &ninfo, &infos, 0);
        fprintf(f, "  kind %d: efficiency %d, PUs ", k, eff);
        print_list(f, set);
        for (unsigned i = 0; i < ninfo; i++)
            fprintf(f, ", %s=%s", infos[i].name, infos[i].value);
        fputc('\n', f);
        hwloc_bitmap_free(set);
    }
    if (t->kinds_error[0])
        fprintf(f, "  note: %s\n", t->kinds_error);
    fprintf(f, "cores:\n");
    for (int c = 0; c < t->ncores; c++) {
        hwloc_obj_t core = hwloc_get_obj_by_type(h, t->core_type, (unsigned)c);
        int pu = hwloc_bitmap_first(core->cpuset);
        fprintf(f, "  core %d: PUs ", c);
        print_list(f, core->cpuset);
        char numa[16];
        int nn = pu >= 0 ? numa_of_pu(h, (unsigned)pu) : -1;
        snprintf(numa, sizeof numa, "%d", nn);
        fprintf(f, ", kind %s, NUMA %s\n", psim_topo_kind_name(t, t->core_kind[c]),
                nn < 0 ? "-" : numa);
    }
    static const hwloc_obj_type_t caches[] = {HWLOC_OBJ_L1CACHE, HWLOC_OBJ_L2CACHE,
                                              HWLOC_OBJ_L3CACHE};
    for (int k = 0; k < 3; k++) {
        int n = hwloc_get_nbobjs_by_type(h, caches[k]);
        if (n <= 0)
            continue;
        hwloc_obj_t o = hwloc_get_obj_by_type(h, caches[k], 0);
        fprintf(f, "L%d cache: %d x %llu KiB\n", k + 1, n,
                (unsigned long long)(o->attr->cache.size / 1024));
    }
    for (int k = 0; k < nodes; k++) {
        hwloc_obj_t node = hwloc_get_obj_by_type(h, HWLOC_OBJ_NUMANODE, (unsigned)k);
        fprintf(f, "NUMA node %d: %llu MiB, PUs ", k,
                (unsigned long long)(node->attr->numanode.local_memory >> 20));
        if (node->cpuset)
            print_list(f, node->cpuset);
        fputc('\n', f);
    }
}
