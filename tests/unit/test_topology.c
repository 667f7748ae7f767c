/* Pinning plans on topologies the test builds itself (hwloc synthetic
 * topologies, restricted and given CPU kinds with hwloc_cpukinds_register),
 * with the exact PU list of every policy. */
#include <stdlib.h>
#include <string.h>

#include <hwloc.h>

#include "check.h"
#include "psim/topology.h"

typedef struct kind_spec {
    const char *pus;  /* PU list, e.g. "0-11" */
    int efficiency;   /* forced efficiency, -1 unranked */
    const char *core_type, *freq;
} kind_spec;

static psim_topo *build(const char *synthetic, const char *keep, const kind_spec *kinds,
                        int nkinds)
{
    hwloc_topology_t h;
    hwloc_topology_init(&h);
    CHECK(hwloc_topology_set_synthetic(h, synthetic) == 0);
    CHECK(hwloc_topology_load(h) == 0);
    if (keep) {
        hwloc_bitmap_t set = hwloc_bitmap_alloc();
        hwloc_bitmap_list_sscanf(set, keep);
        CHECK(hwloc_topology_restrict(h, set, 0) == 0);
        hwloc_bitmap_free(set);
    }
    for (int k = 0; k < nkinds; k++) {
        hwloc_bitmap_t set = hwloc_bitmap_alloc();
        hwloc_bitmap_list_sscanf(set, kinds[k].pus);
        struct hwloc_info_s infos[2];
        unsigned n = 0;
        if (kinds[k].core_type)
            infos[n++] = (struct hwloc_info_s){(char *)"CoreType", (char *)kinds[k].core_type};
        if (kinds[k].freq)
            infos[n++] = (struct hwloc_info_s){(char *)"FrequencyMaxMHz", (char *)kinds[k].freq};
        CHECK(hwloc_cpukinds_register(h, set, kinds[k].efficiency, n, infos, 0) == 0);
        hwloc_bitmap_free(set);
    }
    /* kinds registered unranked must reach psim unranked, or the test would
     * not exercise psim's own ordering */
    for (int k = 0; k < nkinds; k++) {
        if (kinds[k].efficiency >= 0)
            continue;
        int eff = 0;
        unsigned ninfo;
        struct hwloc_info_s *infos;
        CHECK(hwloc_cpukinds_get_info(h, (unsigned)k, NULL, &eff, &ninfo, &infos, 0) == 0);
        CHECK_MSG(eff == -1, "kind %d was ranked by hwloc (efficiency %d)", k, eff);
    }
    psim_error err = {{0}, 0};
    psim_topo *t = psim_topo_wrap(h, &err);
    CHECK(t != NULL);
    CHECK(!psim_topo_is_this_system(t));
    return t;
}

/* The plan's PUs as a comma-separated list. */
static void expect_plan(const psim_topo *t, const char *policy, int threads,
                        const char *pus, const char *notice_part)
{
    psim_pin_policy p;
    psim_pin_plan plan;
    psim_error err = {{0}, 0};
    CHECK(psim_pin_parse(policy, &p, &err) == 0);
    int rc = psim_pin_plan_make(t, &p, threads, &plan, &err);
    CHECK_MSG(rc == 0, "%s: %s", policy, err.msg);
    if (rc)
        return;
    char got[512] = "";
    for (int k = 0; k < plan.threads; k++) {
        char one[16];
        snprintf(one, sizeof one, "%s%d", k ? "," : "", plan.slot[k].pu);
        strcat(got, one);
    }
    CHECK_MSG(strcmp(got, pus) == 0, "--pin=%s threads %d: got %s, want %s", policy,
              threads, got, pus);
    if (notice_part)
        CHECK_MSG(strstr(plan.notice, notice_part) != NULL, "notice '%s' lacks '%s'",
                  plan.notice, notice_part);
    else
        CHECK_MSG(plan.notice[0] == 0, "unexpected notice '%s'", plan.notice);
    psim_pin_plan_free(&plan);
}

static void expect_fail(const psim_topo *t, const char *policy, const char *part)
{
    psim_pin_policy p;
    psim_pin_plan plan;
    psim_error err = {{0}, 0};
    CHECK(psim_pin_parse(policy, &p, &err) == 0);
    CHECK(psim_pin_plan_make(t, &p, 0, &plan, &err) != 0);
    CHECK_MSG(strstr(err.msg, part) != NULL, "'%s' lacks '%s'", err.msg, part);
}

/* 6 P-cores with 2 hardware threads (PUs 0-11) and 8 E-cores with one
 * (PUs 12, 14, ..., 26: the second PU of those cores is removed). */
static void test_hybrid(void)
{
    kind_spec kinds[] = {{"12,14,16,18,20,22,24,26", 0, "IntelAtom", "3900"},
                         {"0-11", 1, "IntelCore", "5000"}};
    psim_topo *t = build("pack:1 core:14 pu:2", "0-12,14,16,18,20,22,24,26", kinds, 2);
    expect_plan(t, "pcores", 0, "0,2,4,6,8,10", NULL);
    expect_plan(t, "ecores", 0, "12,14,16,18,20,22,24,26", NULL);
    expect_plan(t, "cores", 0, "0,2,4,6,8,10,12,14,16,18,20,22,24,26", NULL);
    expect_plan(t, "all", 0, "0,2,4,6,8,10,12,14,16,18,20,22,24,26,1,3,5,7,9,11", NULL);
    expect_plan(t, "pcores", 3, "0,2,4", NULL);
    /* more threads than P-cores: the second hardware threads, then round-robin */
    expect_plan(t, "pcores", 8, "0,2,4,6,8,10,1,3", "oversubscribed");
    expect_plan(t, "pcores", 14, "0,2,4,6,8,10,1,3,5,7,9,11,0,2", "oversubscribed");
    expect_plan(t, "ecores", 10, "12,14,16,18,20,22,24,26,12,14", "oversubscribed");
    expect_plan(t, "numa:0", 0, "0,2,4,6,8,10,12,14,16,18,20,22,24,26", NULL);
    CHECK(strcmp(psim_topo_kind_name(t, 1), "IntelCore") == 0);
    CHECK(strcmp(psim_topo_kind_name(t, 0), "IntelAtom") == 0);
    psim_pin_policy p;
    psim_pin_plan plan;
    psim_error err = {{0}, 0};
    psim_pin_parse("pcores", &p, &err);
    CHECK(psim_pin_plan_make(t, &p, 0, &plan, &err) == 0);
    for (int k = 0; k < plan.threads; k++)
        CHECK(plan.slot[k].kind == 1 && plan.slot[k].core == k);
    psim_pin_plan_free(&plan);
    psim_topo_free(t);
}

static void test_three_kinds(void)
{
    kind_spec kinds[] = {{"0-1", 0, NULL, NULL}, {"2-3", 1, NULL, NULL}, {"4-5", 2, NULL, NULL}};
    psim_topo *t = build("pack:1 core:6 pu:1", NULL, kinds, 3);
    expect_plan(t, "pcores", 0, "4,5", NULL);
    expect_plan(t, "ecores", 0, "0,1", NULL);
    expect_plan(t, "cores", 0, "0,1,2,3,4,5", NULL);
    expect_plan(t, "all", 0, "0,1,2,3,4,5", NULL);
    psim_topo_free(t);
}

static void test_unranked(void)
{
    /* hwloc ranks kinds by CoreType or frequency on its own; this is the
     * case where it does not (HWLOC_CPUKINDS_RANKING=none, or an OS that
     * gives no ranking) */
    setenv("HWLOC_CPUKINDS_RANKING", "none", 1);
    /* efficiency -1: told apart by CoreType, listed in either order */
    kind_spec by_type[] = {{"2-3", -1, "IntelCore", NULL}, {"0-1", -1, "IntelAtom", NULL}};
    psim_topo *t = build("pack:1 core:4 pu:1", NULL, by_type, 2);
    expect_plan(t, "pcores", 0, "2,3", NULL);
    expect_plan(t, "ecores", 0, "0,1", NULL);
    psim_topo_free(t);
    /* ... or by frequency */
    kind_spec by_freq[] = {{"0-1", -1, NULL, "4800"}, {"2-3", -1, NULL, "2400"}};
    t = build("pack:1 core:4 pu:1", NULL, by_freq, 2);
    expect_plan(t, "pcores", 0, "0,1", NULL);
    expect_plan(t, "ecores", 0, "2,3", NULL);
    psim_topo_free(t);
    /* ... or not at all: a clear error, and the kind-blind policies work */
    kind_spec blind[] = {{"0-1", -1, NULL, NULL}, {"2-3", -1, NULL, NULL}};
    t = build("pack:1 core:4 pu:1", NULL, blind, 2);
    expect_fail(t, "pcores", "do not tell them apart");
    expect_fail(t, "ecores", "use --pin=cores");
    expect_plan(t, "cores", 0, "0,1,2,3", NULL);
    psim_topo_free(t);
    unsetenv("HWLOC_CPUKINDS_RANKING");
}

static void test_numa(void)
{
    psim_topo *t = build("pack:1 numa:2 core:4 pu:2", NULL, NULL, 0);
    expect_plan(t, "numa:0", 0, "0,2,4,6", NULL);
    expect_plan(t, "numa:1", 0, "8,10,12,14", NULL);
    expect_plan(t, "numa:1", 6, "8,10,12,14,9,11", "oversubscribed");
    expect_plan(t, "cores", 0, "0,2,4,6,8,10,12,14", NULL);
    expect_fail(t, "numa:2", "has 2 NUMA nodes (0..1)");
    psim_pin_policy p;
    psim_pin_plan plan;
    psim_error err = {{0}, 0};
    psim_pin_parse("cores", &p, &err);
    CHECK(psim_pin_plan_make(t, &p, 0, &plan, &err) == 0);
    for (int k = 0; k < plan.threads; k++)
        CHECK(plan.slot[k].numa == (k < 4 ? 0 : 1));
    psim_pin_plan_free(&plan);
    psim_topo_free(t);
}

static void test_plain(void)
{
    psim_topo *t = build("pack:1 core:4 pu:1", NULL, NULL, 0);
    expect_plan(t, "pcores", 0, "0,1,2,3", "one CPU kind");
    expect_plan(t, "ecores", 2, "0,1", "one CPU kind");
    expect_plan(t, "all", 5, "0,1,2,3,0", "oversubscribed");
    psim_pin_policy p;
    psim_pin_plan plan;
    psim_error err = {{0}, 0};
    CHECK(psim_pin_parse("none", &p, &err) == 0);
    CHECK(psim_pin_plan_make(t, &p, 3, &plan, &err) == 0);
    CHECK(plan.slot == NULL && plan.threads == 3);
    /* binding on a topology that is not this machine does nothing */
    int observed[3] = {7, 7, 7};
    CHECK(psim_pin_apply(t, &plan, observed, &err) == 0);
    CHECK(observed[0] == -1 && observed[2] == -1);
    psim_topo_free(t);
}

static void test_parse(void)
{
    psim_pin_policy p;
    psim_error err = {{0}, 0};
    CHECK(psim_pin_parse("numa:3", &p, &err) == 0 && p.kind == PSIM_PIN_NUMA && p.numa == 3);
    CHECK(psim_pin_parse("numa:", &p, &err) != 0);
    CHECK(psim_pin_parse("numa:-1", &p, &err) != 0);
    CHECK(psim_pin_parse("fast", &p, &err) != 0);
    CHECK(strstr(err.msg, "unknown policy 'fast'") != NULL);
}

/* On this machine: a bound team runs where the plan says. */
static void test_this_machine(void)
{
    psim_error err = {{0}, 0};
    psim_topo *t = psim_topo_load(NULL, &err);
    CHECK(t != NULL && psim_topo_is_this_system(t));
    psim_pin_policy p;
    psim_pin_parse("cores", &p, &err);
    psim_pin_plan plan;
    CHECK(psim_pin_plan_make(t, &p, 0, &plan, &err) == 0);
    int *observed = calloc((size_t)plan.threads, sizeof *observed);
    CHECK(psim_pin_apply(t, &plan, observed, &err) == 0);
    for (int k = 0; k < plan.threads; k++)
        CHECK_MSG(observed[k] == plan.slot[k].pu, "thread %d on PU %d, planned %d", k,
                  observed[k], plan.slot[k].pu);
    free(observed);
    psim_pin_plan_free(&plan);
    psim_topo_free(t);
    CHECK(psim_topo_load("/nonexistent.xml", &err) == NULL);
    CHECK(strstr(err.msg, "/nonexistent.xml: cannot read") != NULL);
}

/* Rank `rank` of `ranks`: its PUs and its share's name. */
static void expect_rank(const psim_topo *t, const char *policy, int threads, int rank,
                        int ranks, int want_rc, const char *pus, const char *share)
{
    psim_pin_policy p;
    psim_pin_plan plan;
    psim_error err = {{0}, 0};
    CHECK(psim_pin_parse(policy, &p, &err) == 0);
    int rc = psim_pin_plan_rank(t, &p, threads, rank, ranks, &plan, &err);
    CHECK_MSG(rc == want_rc, "--pin=%s rank %d of %d: rc %d (%s)", policy, rank, ranks, rc,
              err.msg);
    if (rc == 0) {
        char got[512] = "";
        for (int k = 0; k < plan.threads; k++) {
            char one[16];
            snprintf(one, sizeof one, "%s%d", k ? "," : "", plan.slot[k].pu);
            strcat(got, one);
        }
        CHECK_MSG(strcmp(got, pus) == 0, "--pin=%s rank %d of %d: got %s, want %s", policy,
                  rank, ranks, got, pus);
        CHECK_MSG(strcmp(plan.share, share) == 0, "rank %d of %d: share '%s', want '%s'",
                  rank, ranks, plan.share, share);
    }
    psim_pin_plan_free(&plan);
}

static void test_ranks(void)
{
    psim_topo *t = build("pack:1 numa:8 core:2 pu:1", NULL, NULL, 0);
    expect_rank(t, "cores", 0, 5, 8, 0, "10,11", "NUMA node 5, cores 10-11");
    expect_rank(t, "numa", 0, 1, 4, 0, "4,5,6,7", "NUMA nodes 2-3, cores 4-7");
    expect_rank(t, "numa", 0, 3, 16, 0, "3", "NUMA node 1, core 3");
    expect_rank(t, "cores", 1, 2, 3, 0, "11", "cores 11-15");
    expect_rank(t, "cores", 0, 0, 17, -2, "", "");
    expect_rank(t, "numa", 0, 0, 3, -2, "", "");
    psim_topo_free(t);
    kind_spec kinds[] = {{"12,14,16,18,20,22,24,26", 0, "IntelAtom", "3900"},
                         {"0-11", 1, "IntelCore", "5000"}};
    t = build("pack:1 core:14 pu:2", "0-12,14,16,18,20,22,24,26", kinds, 2);
    expect_rank(t, "cores", 0, 0, 2, 0, "0,2,4,6,8,10", "IntelCore, cores 0-5");
    expect_rank(t, "cores", 3, 1, 2, 0, "12,14,16", "IntelAtom, cores 6-13");
    expect_rank(t, "cores", 0, 2, 7, 0, "8,10", "cores 4-5");
    psim_topo_free(t);
}

int main(void)
{
    test_hybrid();
    test_three_kinds();
    test_unranked();
    test_numa();
    test_plain();
    test_parse();
    test_this_machine();
    test_ranks();
    return check_done();
}
