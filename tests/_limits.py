"""An address-space cap for a child process, one copy for the memory-limit tests.

Reference: the operating system. The child sets its soft ``RLIMIT_AS``
(``resource.setrlimit``, which the kernel enforces) to its own ``VmSize`` (read from
``/proc/self/status``, Linux) plus a headroom, after its imports, so that the work it
then asks for has at most that headroom of address space, whatever the machine's free
pages. The hard limit is kept. Used by tests/common/test_memory_limit_review21.py,
tests/common/test_memory_limit_round27.py and tests/cli/test_cli_refusals.py.
"""

import textwrap

_CAP = """\
import resource
size = 0
with open("/proc/self/status") as fh:
    for line in fh:
        if line.startswith("VmSize:"):
            size = int(line.split()[1]) * 1024
resource.setrlimit(resource.RLIMIT_AS,
                   (int(size + {headroom}), resource.getrlimit(resource.RLIMIT_AS)[1]))
"""


def capped_child(body: str, headroom: float, setup: str = "") -> str:
    """Source of a ``python -c`` child: ``setup``, the cap, then ``body``.

    Parameters
    ----------
    body : str
        Code run under the cap (dedented).
    headroom : float
        Address space [bytes] left above the child's ``VmSize`` once ``setup`` ran.
    setup : str
        Code run before the cap (the imports whose mappings are not the test's subject).

    Returns
    -------
    str
        The child's source.
    """
    return "\n".join((textwrap.dedent(setup), _CAP.format(headroom=repr(float(headroom))),
                      textwrap.dedent(body)))
