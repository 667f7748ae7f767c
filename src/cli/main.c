/* psim: entry point; dispatches to the subcommands. */
#include <string.h>

#include "cli.h"

int main(int argc, char **argv)
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
