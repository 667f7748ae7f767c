/* Pinning for the CLI: --pin, --topology, --mem, --dry-run; psim plan and
 * psim topo. */
#include <getopt.h>
#include <stdlib.h>
#include <string.h>

#include <omp.h>

#include "affinity.h"
#include "cli.h"
#include "launcher.h"
#include "options.h"
#include "paths.h"
#include "pin.h"
#include "device.h"
#include "say.h"
#include "threads.h"
#include "version.h"
#include "psim/topology.h"

struct topo_load {
    const char *xml;
    psim_error *err;
    psim_topo *topo;
};

/* psim_topo_load reads the CPUs the process may use from its threads'
 * masks: called with the start mask back on this thread, it sees every
 * CPU psim was given, even where the OpenMP runtime bound this thread to
 * one of them (OMP_PROC_BIND) or likwid-pin did. */
static int load_topology(void *ctx)
{
    struct topo_load *l = ctx;
    l->topo = psim_topo_load(l->xml, l->err);
    return l->topo ? 0 : -1;
}

static psim_topo *load_topo(const char *xml, psim_error *err)
{
    struct topo_load load = {xml, err, NULL};
    cli_with_start_cpus(load_topology, &load);
    return load.topo;
}

/* "rank 1 of 2" or "rank 5 of 8, local 1 of 4". */
static const char *rank_name(const cli_pin *p, char *buf, size_t len)
{
    int n = snprintf(buf, len, "rank %d of %d", p->rank, p->size);
    if ((p->local_rank != p->rank || p->local_size != p->size) && n > 0 && (size_t)n < len)
        snprintf(buf + n, len - (size_t)n, ", local %d of %d", p->local_rank, p->local_size);
    return buf;
}

/* The plan of this rank's share of the node's ranks: 0, -1 or -2. */
static int plan_rank(cli_pin *p, int threads, psim_error *err)
{
    int rc = psim_pin_plan_rank(p->topo, &p->policy, threads, p->local_rank, p->local_size,
                                &p->plan, err);
    if (rc != 1)
        return rc;
    char who[64], name[32];
    cli_err("psim: warning: %s: its share of --pin=%s (%s) is outside the CPUs the "
            "launcher gave it; pinned within those (start with mpirun --bind-to none or "
            "--map-by ...:PE=%d)", rank_name(p, who, sizeof who),
            psim_pin_name(&p->policy, name, sizeof name), p->plan.share,
            threads > 0 ? threads : p->plan.cores);
    rc = psim_pin_plan_make(p->topo, &p->policy, threads, &p->plan, err);
    snprintf(p->plan.share, sizeof p->plan.share, "the launcher's CPUs");
    return rc;
}

/* Plan: this rank's share under a launcher, else the whole policy. */
static int make_plan(cli_pin *p, int threads, psim_error *err)
{
    p->ranked = p->policy.kind != PSIM_PIN_NONE &&
                cli_launcher_rank(&p->rank, &p->size, &p->local_rank, &p->local_size) &&
                p->local_size > 0;
    if (p->ranked)
        return plan_rank(p, threads, err);
    return psim_pin_plan_make(p->topo, &p->policy, threads, &p->plan, err);
}

int cli_pin_setup(cli_pin *p, int threads, int quiet)
{
    psim_error err = {{0}, 0};
    memset(&p->plan, 0, sizeof p->plan);
    p->plan.threads = threads > 0 ? threads : omp_get_max_threads();
    int needed = p->policy.kind != PSIM_PIN_NONE || p->mem != PSIM_MEM_LOCAL ||
                 p->topology || p->dry_run;
    if (!needed)
        return 0; /* no topology is loaded for a run that does not pin */
    p->topo = load_topo(p->topology, &err);
    int rc = p->topo ? make_plan(p, threads, &err) : -1;
    if (rc) {
        cli_err("psim: %s", err.msg);
        return rc == -2 ? -2 : -1;
    }
    if (p->plan.threads <= 0)
        p->plan.threads = omp_get_max_threads();
    p->plan.threads = cli_threads_cap(p->plan.threads);
    if (p->plan.notice[0] && !quiet)
        cli_err("psim: notice: %s", p->plan.notice);
    if (p->dry_run)
        return 0;
    p->observed = calloc((size_t)p->plan.threads, sizeof *p->observed);
    if (!p->observed) {
        cli_err("psim: out of memory");
        return -1;
    }
    if (psim_mem_apply(p->topo, &p->plan, p->mem, &err) ||
        psim_pin_apply(p->topo, &p->plan, p->observed, &err)) {
        cli_err("psim: %s", err.msg);
        return -1;
    }
    return 0;
}

void cli_pin_free(cli_pin *p)
{
    psim_pin_plan_free(&p->plan);
    psim_topo_free(p->topo);
    free(p->observed);
    p->topo = NULL;
    p->observed = NULL;
}

/* "placement" as JSON members for --stats. */
char *cli_pin_json(const cli_pin *p)
{
    char *s = NULL;
    size_t len = 0;
    FILE *f = open_memstream(&s, &len);
    if (!f)
        return NULL;
    char name[32];
    psim_pin_name(&p->policy, name, sizeof name);
    fprintf(f, "  \"pin\": \"%s\",\n", name);
    if (p->ranked)
        fprintf(f, "  \"rank\": %d,\n  \"ranks\": %d,\n  \"local_rank\": %d,\n"
                   "  \"local_ranks\": %d,\n  \"share\": \"%s\",\n",
                p->rank, p->size, p->local_rank, p->local_size, p->plan.share);
    fprintf(f, "  \"placement\": [");
    for (int k = 0; p->plan.slot && k < p->plan.threads; k++) {
        const psim_pin_slot *s2 = &p->plan.slot[k];
        fprintf(f, "%s\n    {\"thread\": %d, \"pu\": %d, \"observed_pu\": %d, \"core\": %d, "
                   "\"kind\": \"%s\", \"numa\": %d}", k ? "," : "", k, s2->pu,
                p->observed ? p->observed[k] : -1, s2->core,
                psim_topo_kind_name(p->topo, s2->kind), s2->numa);
    }
    fprintf(f, "%s]", p->plan.slot ? "\n  " : "");
    fclose(f);
    return s;
}

/* Where the threads ran when something other than psim placed them. */
static void outside_summary(FILE *f, const psim_sim *s)
{
    const char *by = cli_outside_placement();
    int threads = 0;
    const psim_thread_stats *ts = psim_get_thread_stats(s, &threads);
    if (!by || !ts)
        return;
    fprintf(f, "  thread->PU");
    for (int k = 0; k < threads; k++)
        fprintf(f, " %d->%d", k, ts[k].cpu);
    fprintf(f, " (placed by %s)\n", by);
}

void cli_pin_summary(FILE *f, const cli_pin *p, const psim_sim *s)
{
    if (!p->plan.slot) {
        outside_summary(f, s);
        return;
    }
    if (cli_binders_removed() && psim_topo_is_this_system(p->topo))
        fprintf(f, "  --pin places the threads: %s not given to the OpenMP runtime\n",
                cli_binders_removed());
    if (getenv("LIKWID_PIN") && psim_topo_is_this_system(p->topo))
        fprintf(f, "  --pin places the threads: likwid-pin's placement replaced\n");
    char name[32], who[64];
    int as_planned = 1;
    fprintf(f, "  --pin=%s", psim_pin_name(&p->policy, name, sizeof name));
    if (p->ranked)
        fprintf(f, " (%s: %s)", rank_name(p, who, sizeof who), p->plan.share);
    fprintf(f, ": thread->PU");
    for (int k = 0; k < p->plan.threads; k++) {
        fprintf(f, " %d->%d", k, p->observed ? p->observed[k] : -1);
        as_planned &= p->observed && p->observed[k] == p->plan.slot[k].pu;
    }
    fprintf(f, "%s\n", as_planned ? " (as planned)"
                                  : psim_topo_is_this_system(p->topo)
                                        ? " (NOT as planned: see psim plan)"
                                        : " (foreign topology: not bound)");
}

int cli_pin_option(cli_pin *p, int opt, const char *arg)
{
    psim_error err = {{0}, 0};
    switch (opt) {
    case CLI_OPT_PIN:
        if (psim_pin_parse(arg, &p->policy, &err)) {
            cli_err("psim: %s", err.msg);
            return -1;
        }
        return 0;
    case CLI_OPT_TOPOLOGY:
        p->topology = arg;
        return 0;
    case CLI_OPT_MEM:
        if (strcmp(arg, "local") == 0)
            p->mem = PSIM_MEM_LOCAL;
        else if (strcmp(arg, "interleave") == 0)
            p->mem = PSIM_MEM_INTERLEAVE;
        else {
            cli_err("psim: --mem: unknown policy '%s' (local, interleave)", arg);
            return -1;
        }
        return 0;
    case CLI_OPT_DRY_RUN:
        p->dry_run = 1;
        return 0;
    }
    return -1;
}

static void plan_usage(FILE *f, const char *cmd)
{
    if (strcmp(cmd, "topo") == 0)
        fprintf(f, "usage: psim topo [--topology FILE.xml]\n\n"
                   "Summarise the machine (or an hwloc XML topology): CPU kinds and their\n"
                   "infos, cores, hardware threads, caches, NUMA nodes.\n\n"
                   "options:\n"
                   "      --topology FILE.xml  the hwloc XML topology of another machine\n"
                   "                    to summarise instead of this one\n");
    else
        fprintf(f, "usage: psim plan [--ranks R] [--pin POLICY] [--threads N]\n"
                   "                 [--topology FILE.xml]\n\n"
                   "Print where each thread would run: thread, PU, core, CPU kind, NUMA node\n"
                   "(and rank, with --ranks).\n\n"
                   "options:\n"
                   "      --ranks R     plan R ranks of an MPI launcher on this machine:\n"
                   "                    whole NUMA nodes or CPU kinds each where R fits\n"
                   "                    them, else equal blocks of cores (docs/pinning.md)\n"
                   "      --pin POLICY  pcores, ecores, cores, all, numa, numa:K or none\n"
                   "                    (default: cores), as psim --pin takes them\n"
                   "  -t, --threads N   threads to place (per rank with --ranks; default:\n"
                   "                    one per core of the policy or the rank's share, one\n"
                   "                    per hardware thread with all; with none,\n"
                   "                    OMP_NUM_THREADS, else all cores)\n"
                   "      --topology FILE.xml  the hwloc XML topology of another machine\n"
                   "                    to plan on instead of this one\n");
    fprintf(f, "  -h, --help        show this help\n"
               "  -V, --version     show the version\n");
}

/* psim plan --ranks: every rank's plan; the exit status. */
static int plan_ranks(const cli_pin *p, int threads, int ranks)
{
    psim_pin_plan *plans = calloc((size_t)ranks, sizeof *plans);
    psim_error err = {{0}, 0};
    int rc = plans ? 0 : -1, made = 0;
    if (!plans)
        snprintf(err.msg, sizeof err.msg, "out of memory");
    for (; rc == 0 && made < ranks; made++) {
        rc = psim_pin_plan_rank(p->topo, &p->policy, threads, made, ranks, &plans[made], &err);
        if (rc == 1)
            snprintf(err.msg, sizeof err.msg, "--ranks %d: the share of rank %d (%s) is "
                     "outside this process's CPU mask", ranks, made, plans[made].share);
        if (rc == 0 && plans[made].notice[0])
            cli_err("psim: notice: %s", plans[made].notice);
    }
    if (rc == 0)
        psim_pin_plans_print(stdout, p->topo, plans, ranks);
    else
        cli_err("psim: %s", err.msg);
    for (int r = 0; r < made; r++)
        psim_pin_plan_free(&plans[r]);
    free(plans);
    return rc == 0 ? 0 : rc == -2 ? 2 : 1;
}

/* psim plan / psim topo */
int cli_plan(int argc, char **argv)
{
    static const struct option longs[] = {
        {"pin", required_argument, 0, CLI_OPT_PIN},
        {"topology", required_argument, 0, CLI_OPT_TOPOLOGY},
        {"threads", required_argument, 0, 't'},
        {"ranks", required_argument, 0, CLI_OPT_RANKS},
        {"help", no_argument, 0, 'h'},
        {"version", no_argument, 0, 'V'},
        {0, 0, 0, 0}};
    const char *cmd = argv[0];
    int topo_only = strcmp(cmd, "topo") == 0;
    cli_pin p = {0};
    p.policy.kind = PSIM_PIN_CORES;
    long threads = 0, ranks = 0;
    opterr = 0;
    optind = 1;
    int c;
    while ((c = getopt_long(argc, argv, ":t:hV", longs, NULL)) != -1) {
        if (c == 'h') {
            plan_usage(stdout, cmd);
            return 0;
        } else if (c == 'V') {
            cli_version(stdout);
            return 0;
        } else if (c == 't' && !topo_only) {
            if (cli_long("--threads", optarg, 1, CLI_MAX_THREADS, &threads))
                return 2;
        } else if (c == CLI_OPT_RANKS && !topo_only) {
            if (cli_long("--ranks", optarg, 1, CLI_MAX_THREADS, &ranks))
                return 2;
        } else if ((c == CLI_OPT_PIN && !topo_only) || c == CLI_OPT_TOPOLOGY) {
            if (cli_pin_option(&p, c, optarg))
                return 2;
        } else if (c == ':' || c == '?') {
            cli_bad_option(cmd, argv, c);
            return 2;
        } else {
            cli_err("psim %s: %s is not an option of psim %s (see psim %s --help)", cmd,
                    c == 't' ? "--threads" : c == CLI_OPT_RANKS ? "--ranks" : "--pin", cmd,
                    cmd);
            return 2;
        }
    }
    if (optind < argc) {
        cli_err("psim %s: unexpected argument '%s'", cmd, argv[optind]);
        return 2;
    }
    if (ranks && p.policy.kind == PSIM_PIN_NONE) {
        cli_err("psim plan: --ranks needs a --pin policy other than none");
        return 2;
    }
    /* what it prints must not overwrite the topology it reads */
    char who[16];
    snprintf(who, sizeof who, "psim %s", topo_only ? "topo" : "plan");
    const cli_path in = {"--topology file", p.topology}, out = {NULL, "-"};
    if (cli_check_paths(who, &in, 1, &out, 1))
        return 2;
    psim_error err = {{0}, 0};
    p.topo = load_topo(p.topology, &err);
    if (!p.topo) {
        cli_err("psim: %s", err.msg);
        if (topo_only && !p.topology)   /* the devices, which need no topology */
            cli_device_list(stdout);
        return 1;
    }
    int rc = 0;
    if (topo_only) {
        psim_topo_print(stdout, p.topo);
        if (!p.topology)   /* (a file's topology is another machine's) */
            cli_device_list(stdout);
    } else if (ranks) {
        rc = plan_ranks(&p, (int)threads, (int)ranks);
    } else if (psim_pin_plan_make(p.topo, &p.policy, (int)threads, &p.plan, &err)) {
        cli_err("psim: %s", err.msg);
        rc = 1;
    } else {
        if (!p.plan.slot && p.plan.threads <= 0)
            p.plan.threads = omp_get_max_threads();
        if (p.plan.notice[0])
            cli_err("psim: notice: %s", p.plan.notice);
        psim_pin_plan_print(stdout, p.topo, &p.plan);
    }
    cli_pin_free(&p);
    return rc;
}
