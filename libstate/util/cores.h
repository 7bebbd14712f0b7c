// How many cores this process may use, for the stages' default thread counts.
#pragma once

namespace hapstate {

// The CPUs in this process's affinity mask (what `taskset` or mpirun's binding leave it), at
// least 1.
int usable_cores();

// The processes of this MPI job on this host (OpenMPI's OMPI_COMM_WORLD_LOCAL_SIZE, or Slurm's
// SLURM_NTASKS_PER_NODE); 1 outside mpirun.
int ranks_on_this_host();

// The default worker threads of a stage: the usable cores shared among this host's ranks (a
// coordinating rank solves nothing, so n ranks on a host share its cores as n - 1 workers).
int default_threads();

}  // namespace hapstate
