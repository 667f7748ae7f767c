/* --device and the list of CUDA devices (device.h). */
#include <errno.h>
#include <stdlib.h>
#include <string.h>

#include "device.h"
#include "say.h"
#include "../engine/gpu.h"

/* Device numbers psim takes: more than any machine has. */
#define CLI_MAX_DEVICE 1023

int cli_device_parse(const char *text, int *device)
{
    if (!strcmp(text, "cpu")) {
        *device = -1;
        return 0;
    }
    if (!strcmp(text, "gpu")) {
        *device = 0;
        return 0;
    }
    if (!strncmp(text, "gpu:", 4) && text[4] >= '0' && text[4] <= '9') {
        char *end;
        errno = 0;
        long k = strtol(text + 4, &end, 10);
        if (!*end && !errno && k <= CLI_MAX_DEVICE) {
            *device = (int)k;
            return 0;
        }
    }
    cli_err("psim: --device: '%s' is none of cpu, gpu and gpu:K (K: a CUDA device, 0 to %d)",
            text, CLI_MAX_DEVICE);
    return 2;
}

int cli_device_use(int device)
{
    if (device >= 0 && !psim_gpu_built()) {
        cli_err("psim: --device gpu: psim was built without CUDA (docs/gpu.md: build with nvcc)");
        return 2;
    }
    psim_gpu_use(device);
    return 0;
}

void cli_device_list(FILE *f)
{
    const char *why = "";
    int n = psim_gpu_count(&why);
    if (n == 0) {
        fprintf(f, "CUDA devices: none (%s)\n", why);
        return;
    }
    fprintf(f, "CUDA devices: %d\n", n);
    for (int k = 0; k < n; k++) {
        char d[256];
        psim_gpu_describe(k, d, sizeof d);
        fprintf(f, "  gpu:%d  %s\n", k, d);
    }
}
