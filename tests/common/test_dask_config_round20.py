"""A user's Dask configuration that Dask cannot use (adversarial round 20 PART b, issue 27).

References: Dask's documented configuration sources (YAML files under
``DASK_CONFIG``, read when ``dask`` is imported; ``dask.config.set``) and the
project's rule for a refusal (one line naming what is wrong and where). A malformed
``distributed.yaml`` was refused over three lines (the YAML parser's message after a
blank line); a timeout ``abc`` in the configuration gave Dask's bare quoted
"Invalid time unit: abc. Valid units are: ..." (54 names) and no word of where.
"""

from __future__ import annotations

import subprocess
import sys

import pytest

pytest.importorskip("distributed")


def test_a_malformed_dask_yaml_is_refused_in_one_line_naming_the_file(tmp_path):
    (tmp_path / "distributed.yaml").write_text("distributed:\n  worker: [unclosed\n")
    code = ("from modalinfo.common.deps import require\n"
            "try:\n    require('distributed', 'modalinfo batch')\n"
            "except ValueError as exc:\n    print(repr(str(exc)))\n")
    env = {**__import__("os").environ, "DASK_CONFIG": str(tmp_path)}
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True,
                         text=True, timeout=120, check=True).stdout.strip()
    message = eval(out)  # noqa: S307 - the repr printed above
    assert "\n" not in message
    assert "distributed.yaml" in message and "malformed" in message


# the half-started LocalCluster Dask leaves behind complains in its own __del__ (Dask's
# object, collected after the test): not the refusal under test
@pytest.mark.filterwarnings("ignore::pytest.PytestUnraisableExceptionWarning")
def test_a_timeout_that_does_not_parse_is_named_as_the_dask_configuration(tmp_path):
    import gc

    import dask

    from modalinfo.common.tasks.cluster import open_client

    with dask.config.set({"distributed.comm.timeouts.connect": "abc"}), \
            pytest.raises(ValueError, match=r"time in the Dask configuration does not "
                                            r"parse \(Invalid time unit: abc\).*DASK_"):
        with open_client(n_workers=1, dashboard_address=None):
            pass
    gc.collect()  # the half-started cluster's __del__ runs here, under this test's filter
