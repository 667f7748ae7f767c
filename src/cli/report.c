/* --report: the per-thread, per-phase profile as a table; and the same as
 * JSON members for --stats. */
#include <stdlib.h>
#include <string.h>

#include "pin.h"
#include "report.h"

static const char *kind_of(const cli_pin *p, int cpu)
{
    if (!p->topo)
        return "?";
    return psim_topo_kind_name(p->topo, psim_topo_kind_of_pu(p->topo, cpu));
}

/* max / mean - 1 over the threads, for one phase */
static double imbalance(const psim_thread_stats *ts, int n, int phase)
{
    double max = 0, sum = 0;
    for (int k = 0; k < n; k++) {
        sum += ts[k].busy_s[phase];
        if (ts[k].busy_s[phase] > max)
            max = ts[k].busy_s[phase];
    }
    return sum > 0 ? max / (sum / n) - 1 : 0;
}

void cli_report(FILE *f, const psim_sim *s, const cli_pin *p)
{
    int n;
    const psim_thread_stats *ts = psim_get_thread_stats(s, &n);
    const psim_stats *st = psim_get_stats(s);
    fprintf(f, "\nper-thread profile: busy ms per phase (imbalance = busiest / mean - 1)\n");
    fprintf(f, "%-10s %9s", "phase", "wall ms");
    for (int k = 0; k < n; k++)
        fprintf(f, " %9s%-2d", "thread ", k);
    fprintf(f, " %10s\n", "imbalance");
    for (int ph = 0; ph < st->nphases; ph++) {
        if (st->phase_s[ph] == 0)
            continue;
        fprintf(f, "%-10s %9.1f", psim_phase_name(s, ph), 1e3 * st->phase_s[ph]);
        for (int k = 0; k < n; k++)
            fprintf(f, " %11.1f", 1e3 * ts[k].busy_s[ph]);
        fprintf(f, " %9.1f%%\n", 100 * imbalance(ts, n, ph));
    }
    /* work items and particles of the model's own phases */
    for (int ph = PSIM_PHASE_MODEL; ph < st->nphases; ph++) {
        char label[64];
        snprintf(label, sizeof label, "items (%s)", psim_phase_name(s, ph));
        fprintf(f, "%-20s", label);
        for (int k = 0; k < n; k++)
            fprintf(f, " %11llu", (unsigned long long)ts[k].items[ph]);
        snprintf(label, sizeof label, "particles (%s)", psim_phase_name(s, ph));
        fprintf(f, "\n%-20s", label);
        for (int k = 0; k < n; k++)
            fprintf(f, " %11llu", (unsigned long long)ts[k].particles[ph]);
        fputc('\n', f);
    }
    fprintf(f, "%-20s", "wall collisions");
    for (int k = 0; k < n; k++)
        fprintf(f, " %11llu", (unsigned long long)ts[k].wall_resolutions);
    fprintf(f, "\n%-20s", "CPU");
    for (int k = 0; k < n; k++)
        fprintf(f, " %11d", ts[k].cpu);
    fprintf(f, "\n%-20s", "CPU kind");
    for (int k = 0; k < n; k++)
        fprintf(f, " %11s", kind_of(p, ts[k].cpu));
    fputc('\n', f);
}

char *cli_threads_json(const psim_sim *s, const cli_pin *p)
{
    int n;
    const psim_thread_stats *ts = psim_get_thread_stats(s, &n);
    char *out = NULL;
    size_t len = 0;
    FILE *f = open_memstream(&out, &len);
    if (!f)
        return NULL;
    fprintf(f, "  \"per_thread\": [");
    for (int k = 0; k < n; k++) {
        fprintf(f, "%s\n    {\"thread\": %d, \"cpu\": %d, \"kind\": \"%s\", \"wall_resolutions\": %llu",
                k ? "," : "", k, ts[k].cpu, kind_of(p, ts[k].cpu),
                (unsigned long long)ts[k].wall_resolutions);
        static const char *what[3] = {"busy_s", "items", "particles"};
        for (int w = 0; w < 3; w++) {
            fprintf(f, ",\n     \"%s\": {", what[w]);
            for (int ph = 0; ph < psim_get_stats(s)->nphases; ph++) {
                fprintf(f, "%s\"%s\": ", ph ? ", " : "", psim_phase_name(s, ph));
                if (w == 0)
                    fprintf(f, "%.6f", ts[k].busy_s[ph]);
                else
                    fprintf(f, "%llu", (unsigned long long)(w == 1 ? ts[k].items[ph]
                                                                  : ts[k].particles[ph]));
            }
            fprintf(f, "}");
        }
        fprintf(f, "}");
    }
    fprintf(f, "\n  ],\n  \"imbalance\": {");
    for (int ph = 0; ph < psim_get_stats(s)->nphases; ph++)
        fprintf(f, "%s\"%s\": %.4f", ph ? ", " : "", psim_phase_name(s, ph),
                imbalance(ts, n, ph));
    fprintf(f, "}");
    fclose(f);
    return out;
}
