/* The run command's usage and options (run_options.h). */
#include <errno.h>
#include <getopt.h>
#include <limits.h>
#include <stdlib.h>
#include <string.h>

#include "device.h"
#include "options.h"
#include "paths.h"
#include "pin.h"
#include "run_options.h"
#include "say.h"
#include "threads.h"
#include "version.h"

void output_paths(const run_opts *o, const char **p)
{
    const char *list[RUN_OUTPUTS] = {o->out,         o->trace, o->final,  o->stats,
                                     o->thermo_file, o->dump,  o->restart};
    memcpy(p, list, sizeof list);
}

static void run_usage(FILE *f)
{
    fprintf(f,
"usage: psim [OPTIONS] [SCENE [THREADS]]\n"
"       psim gen [OPTIONS]            write a scene (psim gen --help)\n"
"       psim plan [OPTIONS]           show where threads would run\n"
"       psim topo [--topology FILE]   summarise the machine\n"
"       psim models                   list the models\n"
"\n"
"Run SCENE with a model (psim models lists them).  Scenes of the CS3210\n"
"AY2024/25 format (N, L, r, S, then N lines 'i x y vx vy') run with the\n"
"discrete model by default; scenes of the AY2019/20 format (N, L, r, S, then\n"
"'print' or 'perf', then optionally the particle lines) with the ccd model.\n"
"With -n N, the model makes its source's own initial state of N particles\n"
"instead (the force model: CS267 HW2's, as 'psim -n 1000 -s 1 -o out.txt').\n"
"Without SCENE or -n, run the built-in default scene (20000 disks, density\n"
"0.5, 100 steps).  SCENE '-' reads standard input.  THREADS, as in the\n"
"course's 'sim.perf input.in 8', is the same as --threads.\n"
"\n"
"options:\n"
"  -m, --model NAME  discrete, ccd, force or event (default: the scene's; with\n"
"                    -n, force)\n"
"  -t, --threads N   OpenMP threads (default: OMP_NUM_THREADS, else all cores;\n"
"                    with --pin, one per core of the policy); a step whose\n"
"                    threads are measured slower than one thread runs on one\n"
"      --fixed-threads  every step on all the threads, even where one is\n"
"                    faster (for scaling measurements)\n"
"  -s S              --steps S; with -n, --seed S (CS267's flags)\n"
"      --steps S     run S steps instead of the scene's\n"
"  -n N              the model's own initial state of N particles\n"
"      --seed S      its seed (default 0; 0 is a seed like any other)\n"
"  -O, --option K=V  a model option (psim models lists them); repeatable\n"
"      --naive       --option naive=1: the force model's O(n^2) loops\n"
"      --force-stats --option stats=1: CS267's older absmin and absavg\n"
"      --device D    where the steps run: cpu (default), gpu (the first CUDA\n"
"                    device) or gpu:K (device K); the force model only, the\n"
"                    same numbers as the CPU (docs/gpu.md)\n"
"  -o, --out FILE    what the model's source writes: discrete, the final\n"
"                    state, lines 'S i x y vx vy' in id order; ccd, what its\n"
"                    authors' program prints (default: standard output; the\n"
"                    summary goes to stderr): step 0, every step of a 'print'\n"
"                    scene, and the last step with each disk's pair and wall\n"
"                    collision counts; force, CS267's file: 'n size', then\n"
"                    'x y' frames after steps 1, 11, 21, ... (no file\n"
"                    without -o, as in the course)\n"
"      --trace FILE  write the state after every step 1..S: 'k i x y vx vy'\n"
"      --final FILE  write the state after the last step as --trace writes\n"
"                    it, for any model (the force model's --out is CS267's)\n"
"      --digits N    fixed N decimals (8 gives the course's format); default:\n"
"                    discrete and force, the shortest text that reads back to\n"
"                    the same double; ccd, 8 (as its authors print,\n"
"                    -0.00000000 too).  force's --out: N significant digits\n"
"                    (default 6, as C++ streams print)\n"
"      --substeps K  the 2019 authors' SLOW_FACTOR: velocities divided by K,\n"
"                    steps multiplied by K (lines are numbered by sub-step)\n"
"      --check       validate every step as the course's validator does\n"
"      --stats FILE  write run statistics (phase times, counts, per-thread\n"
"                    profile, placement) as JSON\n"
"      --restart FILE  write the state after the last step as a scene to go\n"
"                    on from: 'psim FILE' runs the next steps exactly as an\n"
"                    unbroken run would (steps numbered on; any model reads\n"
"                    it as a scene)\n"
"      --restart-every N  also write it every N steps, each replacing the\n"
"                    last, with the steps left to run: 'psim FILE' after a\n"
"                    killed run ends where the whole run would have\n"
"      --dump FILE   write frames in extended XYZ (OVITO, VMD, ASE;\n"
"                    psim-animate): steps 0, N, 2N, ... and the last\n"
"      --dump-every N  the frame interval of --dump (default 1)\n"
"      --thermo N    every N steps (and at the start and end) print the\n"
"                    model time, the state's kinetic energy, temperature\n"
"                    (kinetic energy per disk) and momentum, the model's\n"
"                    collision counts since the last row, the pressure from\n"
"                    the collision virial (event model) and the overlapping\n"
"                    pairs, as a table on stderr\n"
"      --thermo-file FILE  the same rows as CSV (without --thermo: the first\n"
"                    and last step)\n"
"      --thermo-speed  add the steps per second of wall time since the last\n"
"                    row (the one column that differs from run to run)\n"
"      --report      print the per-thread, per-phase profile with the load\n"
"                    imbalance of each phase\n"
"      --tile N      cells per tile side, a power of two (default: automatic)\n"
"      --pin POLICY  bind threads with hwloc: pcores, ecores, cores, all,\n"
"                    numa:K or none (default); see psim plan --help.  Threads\n"
"                    stay on the CPUs psim was started with (taskset,\n"
"                    likwid-pin); --pin places them itself, and OMP_PROC_BIND,\n"
"                    OMP_PLACES and GOMP_CPU_AFFINITY are then not given to\n"
"                    the OpenMP runtime; without --pin they (or likwid-pin)\n"
"                    place the threads\n"
"      --topology F  plan against the hwloc XML topology F of another machine\n"
"      --mem POLICY  local (first touch, default) or interleave over NUMA nodes\n"
"      --dry-run     print the thread placement of --pin and exit\n"
"  -q, --quiet       print nothing but errors\n"
"  -h, --help        show this help\n"
"  -V, --version     show the version\n"
"\n"
"Output files appear only when complete.  Results do not depend on the\n"
"thread count or the pinning.  Progress shows after a second on a terminal\n"
"(elsewhere a line every 10 s), also inside a long step.  SIGINT or SIGTERM\n"
"stops a run within a moment, without outputs, and psim ends by the signal\n"
"(status 130, 143); a second one ends it at once.  Exit status: 0 ok,\n"
"1 error (bad input, failed --check, collisions that do not settle), 2 usage.\n");
}

/* The options of the outputs, in the order of output_paths. */
static const char *const output_opts[RUN_OUTPUTS] = {
    "--out", "--trace", "--final", "--stats", "--thermo-file", "--dump", "--restart"};

int check_outputs(const run_opts *o, const char *model_out)
{
    const char *files[RUN_OUTPUTS];
    output_paths(o, files);
    cli_path out[RUN_OUTPUTS];
    for (int k = 0; k < RUN_OUTPUTS; k++)
        out[k] = (cli_path){output_opts[k], files[k]};
    if (model_out && !files[0])
        out[0] = (cli_path){model_out, "-"};
    const cli_path in[] = {{"scene", o->scene}, {"--topology file", o->pin.topology}};
    return cli_check_paths("psim", in, 2, out, RUN_OUTPUTS);
}

static int known_model(const char *name)
{
    for (int k = 0; k < psim_model_count(); k++)
        if (strcmp(psim_model_name(k), name) == 0)
            return 1;
    return 0;
}

/* --seed: a whole number in [0, 2^64). */
static int cli_seed(const char *opt, const char *text, unsigned long long *out)
{
    char *end;
    errno = 0;
    unsigned long long v = strtoull(text, &end, 10);
    if (!*text || *end || errno || text[0] == '-') {
        cli_err("psim: %s: '%s' is not a whole number in [0, 2^64)", opt, text);
        return -1;
    }
    *out = v;
    return 0;
}

/* Append "K=V" to the model options (checked against the model later). */
static int add_option(run_opts *o, const char *kv)
{
    if (!strchr(kv, '=') || strchr(kv, ',')) {
        cli_err("psim: --option: expected NAME=VALUE, got '%s'", kv);
        return -1;
    }
    char *joined;
    if (asprintf(&joined, "%s%s%s", o->options ? o->options : "", o->options ? "," : "",
                 kv) < 0) {
        cli_err("psim: out of memory");
        return -1;
    }
    free(o->options);
    o->options = joined;
    return 0;
}

/* -s is the steps, except after -n where it is CS267's -s SEED. */
static int resolve_s(run_opts *o)
{
    if (!o->s_text)
        return 0;
    if (o->n >= 0) {
        if (o->seed_given) {
            cli_err("psim: -s and --seed both give the seed");
            return -1;
        }
        o->seed_given = 1;
        return cli_seed("-s", o->s_text, &o->seed);
    }
    if (o->steps >= 0) {
        cli_err("psim: -s and --steps both give the steps");
        return -1;
    }
    return cli_long("-s", o->s_text, 0, PSIM_MAX_STEPS, &o->steps);
}

const struct option cli_run_longs[] = {
    {"threads", required_argument, 0, 't'}, {"steps", required_argument, 0, 'P'},
    {"seed", required_argument, 0, 'e'},    {"option", required_argument, 0, 'O'},
    {"naive", no_argument, 0, 'N'},         {"force-stats", no_argument, 0, 'F'},
    {"out", required_argument, 0, 'o'},     {"trace", required_argument, 0, 'T'},
    {"final", required_argument, 0, 'Z'},
    {"digits", required_argument, 0, 'd'},  {"check", no_argument, 0, 'c'},
    {"stats", required_argument, 0, 'S'},   {"tile", required_argument, 0, 'L'},
    {"quiet", no_argument, 0, 'q'},         {"help", no_argument, 0, 'h'},
    {"version", no_argument, 0, 'V'},
    {"pin", required_argument, 0, CLI_OPT_PIN},
    {"topology", required_argument, 0, CLI_OPT_TOPOLOGY},
    {"mem", required_argument, 0, CLI_OPT_MEM},
    {"dry-run", no_argument, 0, CLI_OPT_DRY_RUN},
    {"report", no_argument, 0, 'R'},
    {"fixed-threads", no_argument, 0, 'G'},
    {"model", required_argument, 0, 'm'},
    {"substeps", required_argument, 0, 'K'},
    {"thermo", required_argument, 0, 'H'},
    {"thermo-file", required_argument, 0, 'Y'},
    {"thermo-speed", no_argument, 0, 'J'},
    {"dump", required_argument, 0, 'D'},
    {"dump-every", required_argument, 0, 'E'},
    {"restart", required_argument, 0, 'W'},
    {"restart-every", required_argument, 0, 'X'},
    {"device", required_argument, 0, 'U'},
    {0, 0, 0, 0}};
const char cli_run_shorts[] = ":t:s:o:m:n:O:qhV";

int parse_run(int argc, char **argv, run_opts *o)
{
    memset(o, 0, sizeof *o);
    o->steps = -1;
    o->n = -1;
    o->digits = -1;
    o->substeps = 1;
    o->device = -1;
    opterr = 0;
    int c;
    while ((c = getopt_long(argc, argv, cli_run_shorts, cli_run_longs, NULL)) != -1) {
        switch (c) {
        case 'm':
            if (!known_model(optarg)) {
                cli_err("psim: --model: unknown model '%s' (psim models lists them)", optarg);
                return 2;
            }
            o->model = optarg;
            break;
        case 'K': if (cli_long("--substeps", optarg, 1, 1000000, &o->substeps)) return 2; break;
        case 't': if (cli_long("--threads", optarg, 1, CLI_MAX_THREADS, &o->threads)) return 2; break;
        case 's': o->s_text = optarg; break;
        case 'P': if (cli_long("--steps", optarg, 0, PSIM_MAX_STEPS, &o->steps)) return 2; break;
        case 'n': if (cli_long("-n", optarg, 0, 1000000000L, &o->n)) return 2; break;
        case 'e': if (cli_seed("--seed", optarg, &o->seed)) return 2; o->seed_given = 1; break;
        case 'O': if (add_option(o, optarg)) return 2; break;
        case 'N': if (add_option(o, "naive=1")) return 2; break;
        case 'F': if (add_option(o, "stats=1")) return 2; break;
        case 'o': o->out = optarg; break;
        case 'T': o->trace = optarg; break;
        case 'Z': o->final = optarg; break;
        case 'd': if (cli_long("--digits", optarg, 0, PSIM_DIGITS_MAX, &o->digits)) return 2; break;
        case 'c': o->check = 1; break;
        case 'S': o->stats = optarg; break;
        case 'H': if (cli_long("--thermo", optarg, 1, PSIM_MAX_STEPS, &o->thermo)) return 2; break;
        case 'Y': o->thermo_file = optarg; break;
        case 'J': o->thermo_speed = 1; break;
        case 'D': o->dump = optarg; break;
        case 'W': o->restart = optarg; break;
        case 'X': if (cli_long("--restart-every", optarg, 1, PSIM_MAX_STEPS, &o->restart_every)) return 2; break;
        case 'E': if (cli_long("--dump-every", optarg, 1, PSIM_MAX_STEPS, &o->dump_every)) return 2; break;
        case 'L':
            if (cli_long("--tile", optarg, 1, 1 << 20, &o->tile)) return 2;
            if (o->tile & (o->tile - 1)) {
                cli_err("psim: --tile: %ld is not a power of two", o->tile);
                return 2;
            }
            break;
        case 'q': o->quiet = 1; break;
        case 'R': o->report = 1; break;
        case 'G': o->fixed_threads = 1; break;
        case 'U': if (cli_device_parse(optarg, &o->device)) return 2; break;
        case CLI_OPT_PIN: case CLI_OPT_TOPOLOGY: case CLI_OPT_MEM: case CLI_OPT_DRY_RUN:
            if (cli_pin_option(&o->pin, c, optarg)) return 2;
            break;
        case 'h': run_usage(stdout); return -1;
        case 'V': cli_version(stdout); return -1;
        default:
            cli_bad_option(NULL, argv, c);
            return 2;
        }
    }
    if (resolve_s(o))
        return 2;
    if (o->dump_every && !o->dump) {
        cli_err("psim: --dump-every needs --dump FILE");
        return 2;
    }
    if (!o->dump_every)
        o->dump_every = 1;
    if (o->restart_every && (!o->restart || !strcmp(o->restart, "-"))) {
        cli_err("psim: --restart-every needs --restart FILE (a file: each checkpoint "
                        "replaces the last)");
        return 2;
    }
    if (o->thermo_speed && !o->thermo && !o->thermo_file) {
        cli_err("psim: --thermo-speed needs --thermo N or --thermo-file FILE");
        return 2;
    }
    if (o->thermo_file && !o->thermo)
        o->thermo = LONG_MAX;   /* as LAMMPS' thermo 0: the first and last steps */
    if (o->quiet && o->report) {
        cli_err("psim: -q prints nothing and --report prints the profile: give one of them");
        return 2;
    }
    int rest = argc - optind;
    if (rest > 2) {
        cli_err("psim: too many arguments: '%s' (usage: psim [OPTIONS] [SCENE [THREADS]])",
                argv[optind + 2]);
        return 2;
    }
    if (rest >= 1)
        o->scene = argv[optind];
    if (o->scene && o->n >= 0) {
        cli_err("psim: -n makes the scene: give -n or SCENE '%s', not both", o->scene);
        return 2;
    }
    if (o->seed_given && o->n < 0) {
        cli_err("psim: --seed needs -n (the seed of the model's own initial state)");
        return 2;
    }
    if (rest == 2) {
        long t;
        if (cli_long("THREADS", argv[optind + 1], 1, CLI_MAX_THREADS, &t))
            return 2;
        if (o->threads && o->threads != t) {
            cli_err("psim: --threads %ld and THREADS %ld disagree", o->threads, t);
            return 2;
        }
        o->threads = t;
    }
    return check_outputs(o, NULL);
}
