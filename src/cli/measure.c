/* What the program measures of a run around the library (measure.h). */
#include <stdio.h>
#include <sys/resource.h>

#include "measure.h"
#include "../engine/timer.h"

long long cli_peak_rss(void)
{
    FILE *f = fopen("/proc/self/status", "r");
    long long kb = 0;
    if (f) {
        char line[256];
        while (fgets(line, sizeof line, f))
            if (sscanf(line, "VmHWM: %lld kB", &kb) == 1)
                break;
        fclose(f);
    }
    if (kb <= 0) {
        struct rusage ru;
        if (getrusage(RUSAGE_SELF, &ru) == 0)
            kb = ru.ru_maxrss;   /* kilobytes on Linux */
    }
    return kb * 1024;
}

double cli_output_begin(const psim_sim *s)
{
    (void)s;   /* in a build without LIKWID markers */
    psim_region_begin(psim_get_stats(s)->threads, psim_phase_name(s, PSIM_PHASE_OUTPUT));
    return psim_now();
}

void cli_output_end(psim_sim *s, double t0)
{
    psim_add_output_time(s, psim_now() - t0);
    psim_region_end(psim_get_stats(s)->threads, psim_phase_name(s, PSIM_PHASE_OUTPUT));
}
