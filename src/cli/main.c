/* psim: entry point; checks the environment's thread count, dispatches
 * to the subcommands, reports a standard output that could not be
 * written (a full disk, /dev/full, a closed pipe) and ends by the signal
 * that stopped a run. */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"

static int command(int argc, char **argv)
{
    if (argc > 1 && strcmp(argv[1], "gen") == 0)
        return cli_gen(argc - 1, argv + 1);
    if (argc > 1 && (strcmp(argv[1], "plan") == 0 || strcmp(argv[1], "topo") == 0))
        return cli_plan(argc - 1, argv + 1);
    if (argc > 1 && strcmp(argv[1], "models") == 0)
        return cli_models(argc - 1, argv + 1);
    if (argc > 1 && strcmp(argv[1], "run") == 0)
        return cli_run(argc - 1, argv + 1);
    return cli_run(argc, argv);
}

int main(int argc, char **argv)
{
    if (cli_env_threads())
        return 2;
    cli_set_argv(argv);
    int rc = command(argc, argv);
    if ((fflush(stdout) != 0 || ferror(stdout)) && rc == 0) {
        fprintf(stderr, "psim: <stdout>: write failed: %s\n", strerror(errno ? errno : EIO));
        rc = 1;
    }
    cli_interrupt_raise();   /* a run stopped by SIGINT or SIGTERM ends by it */
    return rc;
}
