"""``write_table`` under an address-space limit (round 32 PART b, b56).

References: the files on disk (read back with the standard library's ``csv``) and
pyarrow's own public allocator API (``default_memory_pool`` / ``system_memory_pool``).
Under ``ulimit -v`` pyarrow's default allocator crashed a batch with SIGSEGV inside
``pyarrow.parquet.write_table`` after every row had run: the system allocator is now
used while a limit is set, and pyarrow's default is left as found.
"""
import pytest

pa = pytest.importorskip("pyarrow")
pq = pytest.importorskip("pyarrow.parquet")

from modalinfo.common import memory  # noqa: E402
from modalinfo.common.tasks import rows as rows_mod  # noqa: E402

ROWS = [{"log": "a.npz", "x": 1.5}, {"log": "b.npz", "x": 2.5}]


def test_system_allocator_under_a_limit_and_default_restored(tmp_path, monkeypatch):
    seen = []
    real = pq.write_table

    def spy(table, where, **kwargs):
        seen.append(pa.default_memory_pool().backend_name)
        return real(table, where, **kwargs)

    monkeypatch.setattr(pq, "write_table", spy)
    before = pa.default_memory_pool().backend_name
    monkeypatch.setattr(rows_mod, "address_space_limit_bytes", lambda: 8e9)
    rows_mod.write_table(ROWS, tmp_path, "limited")
    monkeypatch.setattr(rows_mod, "address_space_limit_bytes", memory.address_space_limit_bytes)
    rows_mod.write_table(ROWS, tmp_path, "free")
    assert seen[0] == pa.system_memory_pool().backend_name
    assert pa.default_memory_pool().backend_name == before
    assert pq.read_table(tmp_path / "limited.parquet").to_pylist() == ROWS
