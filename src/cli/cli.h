/* The psim command line: its subcommands, each given main's arguments
 * after the subcommand's name; the exit status. */
#ifndef PSIM_CLI_H
#define PSIM_CLI_H

int cli_run(int argc, char **argv);   /* psim [OPTIONS] [SCENE [THREADS]] */
int cli_gen(int argc, char **argv);   /* psim gen [OPTIONS] */
int cli_plan(int argc, char **argv);  /* psim plan | psim topo */
int cli_models(int argc, char **argv); /* psim models */

#endif
