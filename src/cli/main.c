/* psim: entry point; makes sure the standard descriptors are open,
 * checks the environment's thread count, dispatches to the subcommands,
 * reports a standard output that could not be written (a full disk,
 * /dev/full, a closed pipe) and ends by the signal that stopped a run. */
#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cli.h"
#include "interrupt.h"
#include "provenance.h"
#include "say.h"
#include "threads.h"
#include "../engine/dist.h"

static int command(int argc, char **argv)
{
    if (argc > 1 && strcmp(argv[1], "run") == 0)
        return cli_run(argc - 1, argv + 1);
    if (argc < 2 || (strcmp(argv[1], "gen") && strcmp(argv[1], "plan") &&
                     strcmp(argv[1], "topo") && strcmp(argv[1], "models")))
        return cli_run(argc, argv);
    cli_interrupt_watch();   /* (a run starts it after its OpenMP threads) */
    if (strcmp(argv[1], "gen") == 0)
        return cli_gen(argc - 1, argv + 1);
    if (strcmp(argv[1], "models") == 0)
        return cli_models(argc - 1, argv + 1);
    return cli_plan(argc - 1, argv + 1);
}

/* Descriptors 0, 1 and 2 open before psim opens anything: a file opened
 * later would otherwise take a closed one's number and get what is meant
 * for standard output or error, or be read as standard input.  A closed
 * one gets /dev/null opened the other way round (write-only for input,
 * read-only for output, as gnulib's stdopen does), so that using it still
 * fails as using a closed descriptor does: a '-' output to a closed
 * standard output is a write error, not a silent loss.  0, or -1 when one
 * cannot be opened (no /dev/null: the root folder, read-only, instead). */
static int open_std_fds(void)
{
    for (int fd = 0; fd <= 2; fd++) {
        if (fcntl(fd, F_GETFD) >= 0 || errno != EBADF)
            continue;
        /* the lowest free number: fd itself, the ones below being open */
        int got = open("/dev/null", fd == 0 ? O_WRONLY : O_RDONLY);
        if (got < 0)
            got = open("/", O_RDONLY | O_DIRECTORY);
        if (got != fd) {
            if (got >= 0)
                close(got);
            return -1;
        }
    }
    return 0;
}

int main(int argc, char **argv)
{
    if (open_std_fds()) {
        cli_err("psim: cannot open /dev/null on a closed standard descriptor");
        return 1;
    }
    cli_interrupt_start();   /* before any other thread, which inherits the mask */
    if (cli_env_threads())
        return 2;
    cli_set_argv(argv);
    /* MPI, when a launcher started psim (src/engine/dist.h) */
    psim_error err = {{0}, 0};
    if (psim_dist_start(&argc, &argv, &err) < 0) {
        cli_err("psim: %s", err.msg);
        return 2;
    }
    int rc = command(argc, argv);
    psim_dist_finish();
    if ((fflush(stdout) != 0 || ferror(stdout)) && rc == 0) {
        cli_err("psim: <stdout>: write failed: %s", strerror(errno ? errno : EIO));
        rc = 1;
    }
    cli_interrupt_raise();   /* a run stopped by SIGINT or SIGTERM ends by it */
    return rc;
}
