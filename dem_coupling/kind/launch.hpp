// Launching granflow-dem as a subprocess (under mpirun for more than one rank).
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace granflow::dem {

// Path of the granflow-dem binary: $GRANFLOW_DEM_DRIVER, else the one built with granflow.
std::filesystem::path driver_path();

// argv of the run: [mpirun --oversubscribe [--allow-run-as-root] -np N] driver in.granflow.
std::vector<std::string> driver_command(int ranks, const std::string& deck_name);

// The environment granflow-dem starts with: `inherited` (NAME=value entries), plus
// OMPI_ALLOW_RUN_AS_ROOT(_CONFIRM)=1 for root. When this process is itself a rank of an mpirun
// (`inside_mpi_job`: a sweep distributed over ranks, docs/parallel-runs.md), the variables Open MPI
// and PMIx set for that job's ranks (OMPI_* except OMPI_ALLOW_RUN_AS_ROOT*, PMIX_*) are dropped:
// inherited, they make granflow-dem's MPI_Init, or the nested mpirun of dem.ranks > 1, try to
// join the parent job instead of starting a job of its own.
std::vector<std::string> driver_environment(const std::vector<std::string>& inherited,
                                            bool inside_mpi_job, bool root);

// Runs `command` in `directory` with stdout+stderr to `output_file`; calls `poll` about every
// `poll_seconds` while it runs, in the environment of driver_environment (this process's). Returns
// the exit status (128 + signal when killed; 127, with an "ERROR: granflow: cannot start ..." line
// appended to `output_file`, when the program cannot be started). Started without a shell.
int run_in_directory(const std::vector<std::string>& command,
                     const std::filesystem::path& directory,
                     const std::filesystem::path& output_file, const std::function<void()>& poll,
                     double poll_seconds = 2.0);

// The first "ERROR..." line (LIGGGHTS / granflow-dem / MPI) of a run's output, or "".
std::string first_error_line(const std::filesystem::path& output_file);

}  // namespace granflow::dem
