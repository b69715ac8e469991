"""Mutation round 35 (review35): the lossy-storage note is said of the file that was stored so.

``cli.shared.input_notes`` says ``metadata["lossy_storage"]`` (round 52 PART b: HDF5's
scale-offset filter, FITS tile quantization) only when the file read is the one whose
writer stored it so (``metadata["source_file"]``): a ``modalinfo convert`` output keeps
the metadata of its source, and the note would name the NPZ as stored by HDF5's filter.
Reference: the files are written with h5py (``scaleoffset=0``) and by ``modalinfo
convert``; the file names are compared by hand.
"""
from __future__ import annotations

from pathlib import Path

import h5py
import numpy as np

from modalinfo.cli import main
from modalinfo.cli.shared import input_notes
from modalinfo.io import load


def test_the_note_names_the_lossy_file_and_not_its_converted_copy(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    x = 0.1 * np.random.default_rng(35).standard_normal((400, 6))
    with h5py.File("so.h5", "w") as f:
        f.create_dataset("coeffs", data=x, chunks=(100, 6), scaleoffset=0)
    assert main(["convert", "so.h5", "o.npz", "--rate", "1000", "--quiet"]) == 0
    original = [n for n in input_notes(load("so.h5", rate=1000.0), Path("so.h5"))
                if "scale-offset" in n]
    assert len(original) == 1 and original[0].startswith("'so.h5': ")
    copy = load("o.npz")
    assert copy.metadata["source_file"] == "so.h5"  # the copy keeps its source's record
    assert not [n for n in input_notes(copy, Path("o.npz")) if "scale-offset" in n]
