# CGMS: coarse-grained multiscale model of plant-tissue drying (LAMMPS plugin)
# This software is distributed under the GNU General Public License version 2;
# see the LICENSE file in the top-level directory.
"""A command under ``mpirun`` (``cgms dry``, doc/drying.md, Limits): every process runs
the same Python and LAMMPS splits the beads; process 0 alone claims the folder, writes
files and speaks, and every process ends with the same status, also when only one of
them failed (the others would otherwise wait for it in LAMMPS for ever)."""

import os
import sys
import traceback

#: the commands that run under mpirun
COMMANDS = ("dry",)
#: the launchers' (world size, rank) variables: Open MPI, MPICH and Intel MPI (Hydra),
#: MVAPICH. They are read before MPI starts, to silence the other processes before the
#: options are parsed
LAUNCHERS = (("OMPI_COMM_WORLD_SIZE", "OMPI_COMM_WORLD_RANK"), ("PMI_SIZE", "PMI_RANK"),
             ("MV2_COMM_WORLD_SIZE", "MV2_COMM_WORLD_RANK"))


def launched():
    """``(rank, size)`` the MPI launcher gave this process; ``(0, 1)`` without one."""
    for size, rank in LAUNCHERS:
        if size in os.environ:
            return int(os.environ.get(rank, 0)), int(os.environ[size])
    return 0, 1


def one_voice(argv):
    """Under mpirun, a command of :data:`COMMANDS` speaks through process 0 only (its
    messages, also those of a bad option, would otherwise come once per process)."""
    if argv[:1] and argv[0] in COMMANDS and launched()[0] > 0:
        sys.stdout = sys.stderr = open(os.devnull, "w")


class Stopped(Exception):
    """A failure every process agreed on; its line is printed, ``status`` is the exit
    status of every process."""

    def __init__(self, status):
        super().__init__(status)
        self.status = status


class World:
    """The processes of one command. ``comm``: mpi4py's COMM_WORLD, or None (one process:
    everything runs as it does without mpirun). ``failure(err)``: the exit status and
    one-line message of an exception (cgms.cli.errors.failure)."""

    def __init__(self, comm=None, failure=None):
        self.comm, self.failure = comm, failure
        self.rank = comm.Get_rank() if comm else 0
        self.size = comm.Get_size() if comm else 1

    def together(self, step):
        """``step()`` on every process, and its value; when it raised on any process, the
        first such process's message is printed once and every process raises
        :class:`Stopped` with its status (a step must not be collective in LAMMPS: the
        processes it did not fail on would wait there). One process: ``step()`` as is."""
        if self.comm is None:
            return step()
        try:
            value, failed = step(), None
        except Stopped:             # a nested step's failure, already agreed and printed
            raise
        except Exception as err:
            if os.environ.get("CGMS_DEBUG"):     # where, as cli.main shows it
                traceback.print_exc()
            value, failed = None, self.failure(err)
        failures = [f for f in self.comm.allgather(failed) if f]
        if failures:
            status, line = failures[0]
            if self.rank == 0:
                print(line, file=sys.stderr, flush=True)
            raise Stopped(status)
        return value

    def first(self, value):
        """Process 0's ``value`` on every process."""
        return value if self.comm is None else self.comm.bcast(value, root=0)


def world(failure):
    """The :class:`World` of this process: mpi4py's COMM_WORLD under an MPI launcher
    (MPI starts here, before LAMMPS, which then uses it), else one process. RuntimeError
    under mpirun without mpi4py (every process alike)."""
    if launched()[1] == 1:
        return World()
    try:
        from mpi4py import MPI
    except ImportError:
        raise RuntimeError("under mpirun the processes need mpi4py to agree on the results "
                           "folder (Debian: python3-mpi4py; ./cgms setup installs it)") from None
    return World(MPI.COMM_WORLD, failure)
