/* The rank an MPI launcher started this process as (launcher.c). */
#ifndef PSIM_CLI_LAUNCHER_H
#define PSIM_CLI_LAUNCHER_H

/* Read from the environment, before any MPI call: Open MPI's
 * OMPI_COMM_WORLD_{RANK,SIZE,LOCAL_RANK,LOCAL_SIZE}, else PMIX_RANK, else
 * PMI_RANK/PMI_SIZE (with MPICH's MPI_LOCALRANKID/MPI_LOCALNRANKS), else
 * Slurm's SLURM_PROCID/SLURM_NTASKS/SLURM_LOCALID (with
 * SLURM_NTASKS_PER_NODE).  Returns 1 when a launcher started the process
 * (a rank variable present, or a size above 1), else 0 with rank 0 of 1.
 * A size the environment does not give is 0 (unknown); without a node's
 * own rank and count, local_rank and local_size are rank and size (every
 * rank on this node).  Any pointer may be NULL. */
int cli_launcher_rank(int *rank, int *size, int *local_rank, int *local_size);

#endif
