"""Guards refuse before allocating under an address-space limit (adversarial round 27 a).

Reference: the operating system. Each case runs in a child process whose
``RLIMIT_AS`` is set (``resource.setrlimit``), after its imports, to its ``VmSize`` plus 1 GiB, a
cap the kernel enforces; the work asked for needs about 3 GiB (``Pupil(8000)``: six
8000 x 8000 float64 grids = 2.9 GiB; 12,000 K-L modes of 36,045 Zernikes: 3.2 GiB of
eigenvectors; 199 block-bootstrap resamples of 10^6 rows: 1.5 GiB of indices), far
below the machine's free pages. Expected: the library's own ``ValueError`` naming
the argument, before numpy's ``MemoryError``. Before the fix the guards compared with
the free physical pages only and numpy raised ``MemoryError`` after a partial
allocation.
"""

import subprocess
import sys

import pytest

from .._limits import capped_child

resource = pytest.importorskip("resource")

CHILD = capped_child(setup="""
    import sys
    from modalinfo.bases import KLBasis, Pupil
    from modalinfo.information.resampling import check_index_memory
""", headroom=2**30, body="""
    case = sys.argv[1]
    try:
        if case == "pupil":
            Pupil(8000)
        elif case == "kl":
            KLBasis.from_turbulence(Pupil(400), 12000)
        else:
            check_index_memory(199, 10**6)
    except ValueError as exc:
        print("ValueError:", exc)
    except MemoryError as exc:
        print("MemoryError:", type(exc).__name__)
    else:
        print("accepted")
""")


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="reads /proc/self/status")
@pytest.mark.parametrize(("case", "names"), [("pupil", "`n_pixels`"), ("kl", "`n_modes`"),
                                             ("indices", "`n_resamples`")])
def test_guards_refuse_under_an_address_space_limit(case, names):
    out = subprocess.run([sys.executable, "-c", CHILD, case], capture_output=True, text=True,
                         timeout=120, check=True).stdout
    assert out.startswith("ValueError:"), out
    assert names in out
