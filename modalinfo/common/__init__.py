"""The ground floor: plumbing shared by every package (modalinfo, closedloop, paper_figures).

Nothing here is about wavefronts; everything here is needed by more than one command
package. The rule (``docs/ARCHITECTURE.md``, "The ground floor"): shared plumbing goes
here, never in a command package, and this floor imports nothing of the project above
it. Import the modules by name (this ``__init__`` imports none of them, so a module of
the floor costs only itself):

validation
    Argument checks whose messages name the argument, the rule and the value.
jit
    The one numba decorator of every kernel.
memory
    The machine's available, free and physical memory [bytes].
sizes
    The one size parser (SI and binary units, without dask) and formatter (binary units).
files
    Atomic writes and path checks.
folders
    Output folders: the free-space and writability check, the lock of one run per folder.
deps
    The optional ``dist`` extra, required with a one-line message.
cli
    The command-line base: parser, one-line errors, exit codes, output and cluster checks.
tasks
    The resumable Dask task runner (keys, rows, threads, cluster, watch, runner).
startup
    Checks a command makes before its heavy imports (the current folder exists).
"""
