/* Fuzz target: the topology path (--topology FILE, an hwloc XML file):
 * load it, then plan every pinning policy on it for a few thread counts. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

#include "psim/topology.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    /* hwloc's own XML parser, not its libxml2 plugin: the plugin leaks
     * 112 bytes on a malformed XML declaration (docs/reliability.md), in
     * code that is neither psim's nor reachable from its error path */
    setenv("HWLOC_LIBXML_IMPORT", "0", 0);
    char path[] = "/tmp/psim-fuzz-topo-XXXXXX";
    int fd = mkstemp(path);
    if (fd < 0)
        return 0;
    FILE *f = fdopen(fd, "w");
    if (!f || fwrite(data, 1, size, f) != size) {
        if (f)
            fclose(f);
        unlink(path);
        return 0;
    }
    fclose(f);
    psim_error err = {{0}, 0};
    psim_topo *t = psim_topo_load(path, &err);
    unlink(path);
    if (!t)
        return 0;
    static const char *policies[] = {"none", "pcores", "ecores", "cores", "all", "numa",
                                     "numa:0", "numa:1"};
    for (size_t k = 0; k < sizeof policies / sizeof policies[0]; k++) {
        psim_pin_policy pol;
        if (psim_pin_parse(policies[k], &pol, &err))
            continue;
        for (int threads = 1; threads <= 9; threads += 4) {
            psim_pin_plan plan;
            if (psim_pin_plan_make(t, &pol, threads, &plan, &err) == 0)
                psim_pin_plan_free(&plan);
        }
    }
    psim_topo_free(t);
    return 0;
}
