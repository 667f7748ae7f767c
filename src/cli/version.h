/* What psim is: its release, the git commit it was built from and the
 * build's options (version.c; the commit in the generated git_commit.c). */
#ifndef PSIM_CLI_VERSION_H
#define PSIM_CLI_VERSION_H
#include <stdio.h>

/* --version of psim and of every subcommand (release, git commit, build) */
void cli_version(FILE *f);
extern const char psim_git_commit[];

#endif
