/* The run command's options: psim [OPTIONS] [SCENE [THREADS]]. */
#ifndef PSIM_CLI_RUN_OPTIONS_H
#define PSIM_CLI_RUN_OPTIONS_H
#include <getopt.h>
#include <sys/stat.h>

#include "pin.h"

typedef struct run_opts {
    const char *scene, *out, *trace, *final, *stats, *model, *thermo_file, *dump, *restart;
    long dump_every;        /* --dump-every N (default 1) */
    long restart_every;     /* --restart-every N (0: at the end only) */
    long threads, steps, digits, tile, substeps;
    long thermo;            /* --thermo N (0: none; LONG_MAX: first and last) */
    int thermo_speed;       /* --thermo-speed */
    long n;                 /* -n: the model's own initial state (-1: none) */
    unsigned long long seed;
    const char *s_text;     /* -s: the steps, or with -n the seed (CS267) */
    int seed_given;
    char *options;          /* --option, --naive, --force-stats: "K=V,..." */
    char label[96];         /* the scene, for messages */
    int check, quiet, report, fixed_threads;
    int device;             /* --device: -1 the CPU, K CUDA device K */
    cli_pin pin;
    struct stat scene_st;   /* the scene file when it was read */
    int scene_st_ok;
    double read_s;          /* reading (or making) the scene */
} run_opts;

/* The run's output files, in one order everywhere: the model's own
 * (--out), --trace, --final, --stats, --thermo-file, --dump, --restart. */
#define RUN_OUTPUTS 7
void output_paths(const run_opts *o, const char **p);
/* No output may overwrite an input (the scene, the --topology file) or
 * share its file or stream with another output, under any name
 * (cli_check_paths); model_out, if not NULL, names the model's output
 * written to standard output without --out.  0, or 2 after one line. */
int check_outputs(const run_opts *o, const char *model_out);

/* The options of argv into o: 0, 2 after one line on a usage error, or
 * -1 when an option (--help, --version) has done all there is to do. */
int parse_run(int argc, char **argv, run_opts *o);

/* The run's options, for parse_run and the start's reading of them. */
extern const struct option cli_run_longs[];
extern const char cli_run_shorts[];

#endif
