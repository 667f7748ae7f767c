/* psim gen: write a scene the way the course generator does. */
#include <getopt.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "options.h"
#include "outfile.h"
#include "progress.h"
#include "say.h"
#include "version.h"
#include "../io/scene.h"

static void gen_usage(FILE *f)
{
    fprintf(f,
"usage: psim gen [OPTIONS]\n"
"\n"
"Write a CS3210 AY2024/25 scene.  Positions are uniform in [0, L] (the course\n"
"generator's rule, overlaps allowed) unless --place says otherwise; velocity\n"
"components are uniform in [vmin, vmax].  Prints the density to stderr.\n"
"\n"
"options:\n"
"  -n, --n N           particles (default 1000)\n"
"  -L, --L L           box side (default: from --density, else 100)\n"
"  -r, --r R           radius (default 1)\n"
"      --density D     choose L so that N*pi*r^2/L^2 = D\n"
"  -s, --steps S       steps (default 100)\n"
"      --vmin V        lowest velocity component (default -1)\n"
"      --vmax V        highest velocity component (default 1)\n"
"      --seed K        random seed (default 1)\n"
"      --place P       uniform (default), nonoverlap (random, no overlaps) or\n"
"                      lattice (jittered square lattice, no overlaps)\n"
"  -o, --out FILE      write here instead of standard output\n"
"  -h, --help          show this help\n"
"  -V, --version       show the version\n");
}

static int parse_place(const char *s, psim_place *p)
{
    if (!strcmp(s, "uniform"))
        *p = PSIM_PLACE_UNIFORM;
    else if (!strcmp(s, "nonoverlap"))
        *p = PSIM_PLACE_NONOVERLAP;
    else if (!strcmp(s, "lattice"))
        *p = PSIM_PLACE_LATTICE;
    else {
        cli_err("psim gen: --place: unknown placement '%s' (uniform, nonoverlap, lattice)", s);
        return -1;
    }
    return 0;
}

int cli_gen(int argc, char **argv)
{
    static const struct option longs[] = {
        {"n", required_argument, 0, 'n'},      {"L", required_argument, 0, 'L'},
        {"r", required_argument, 0, 'r'},      {"density", required_argument, 0, 'D'},
        {"steps", required_argument, 0, 's'},  {"vmin", required_argument, 0, 'a'},
        {"vmax", required_argument, 0, 'b'},   {"seed", required_argument, 0, 'k'},
        {"place", required_argument, 0, 'p'},  {"out", required_argument, 0, 'o'},
        {"help", no_argument, 0, 'h'},         {"version", no_argument, 0, 'V'},
        {0, 0, 0, 0}};
    psim_gen_params p = {.n = 1000, .L = 0, .r = 1, .steps = 100, .vmin = -1,
                         .vmax = 1, .seed = 1, .place = PSIM_PLACE_UNIFORM};
    double density = 0, seed = 1;
    const char *out = NULL;
    opterr = 0;
    optind = 1;
    int c;
    while ((c = getopt_long(argc, argv, ":n:L:r:s:o:hV", longs, NULL)) != -1) {
        int bad = 0;
        switch (c) {
        case 'n': bad = cli_long("--n", optarg, 0, 2147483647L, &p.n); break;
        case 'L': bad = cli_double("--L", optarg, 1e-300, 1e300, &p.L); break;
        case 'r': bad = cli_double("--r", optarg, 1e-300, 1e300, &p.r); break;
        case 'D': bad = cli_double("--density", optarg, 1e-12, 100, &density); break;
        case 's': bad = cli_long("--steps", optarg, 0, 1000000000L, &p.steps); break;
        case 'a': bad = cli_double("--vmin", optarg, -1e300, 1e300, &p.vmin); break;
        case 'b': bad = cli_double("--vmax", optarg, -1e300, 1e300, &p.vmax); break;
        case 'k': bad = cli_double("--seed", optarg, 0, 9007199254740992.0, &seed); break;
        case 'p': bad = parse_place(optarg, &p.place); break;
        case 'o': out = optarg; break;
        case 'h': gen_usage(stdout); return 0;
        case 'V': cli_version(stdout); return 0;
        default:
            cli_bad_option("gen", argv, c);
            return 2;
        }
        if (bad)
            return 2;
    }
    if (optind < argc) {
        cli_err("psim gen: unexpected argument '%s' (see psim gen --help)", argv[optind]);
        return 2;
    }
    if (p.vmin > p.vmax) {
        cli_err("psim gen: --vmin %g is above --vmax %g", p.vmin, p.vmax);
        return 2;
    }
    if (density > 0 && p.L > 0) {
        cli_err("psim gen: give --L or --density, not both");
        return 2;
    }
    if (p.L <= 0)
        p.L = density > 0 ? sqrt((double)p.n * M_PI * p.r * p.r / density) : 100;
    if (seed != floor(seed)) {
        cli_err("psim gen: --seed: expected a whole number, got %g", seed);
        return 2;
    }
    p.seed = (uint64_t)seed;
    psim_error err = {{0}, 0};
    psim_scene sc = {0};
    if (psim_scene_generate(&p, &sc, &err)) {
        cli_err("psim gen: %s", err.msg);
        return err.usage ? 2 : 1;   /* options that ask the impossible are usage */
    }
    outfile o;
    int rc = 1;
    if (outfile_open(&o, out ? out : "-") == 0) {
        cli_io_begin("writing", o.name, 0);
        psim_scene_write(o.f, &sc); /* a failed write shows in the commit */
        cli_io_end();
        if (outfile_commit(&o) == 0)
            rc = 0;
    }
    if (rc == 0)
        cli_err("psim gen: %ld disks, L %.17g, r %g, density %.4f", sc.n,
                sc.L, sc.r, psim_scene_density(&sc));
    psim_scene_clear(&sc);
    return rc;
}
