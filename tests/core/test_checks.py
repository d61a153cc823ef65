"""Inputs checked before any work (railcontact.core.checks)."""

import os

import numpy as np
import pytest

from railcontact.core.checks import (MAX_GRID_ELEMENTS, SHOWN_CHARACTERS, check_grid_size,
                                     check_job_size, check_output, shown)
from railcontact.core.errors import InputError, ResourceError


def test_a_long_value_is_cut_and_an_array_named_by_its_shape():
    big = np.zeros(6_000_000)                              # 48 MB
    assert shown(big) == "array of shape (6000000,)"
    text = shown(list(range(100_000)))
    assert len(text) <= SHOWN_CHARACTERS + 20 and text.endswith("(100000 items)")
    assert shown("abc") == "'abc'" and shown(np.arange(3)) == "array([0, 1, 2])"


def test_output_file_checks(tmp_path):
    assert check_output(tmp_path / "a.nc") == tmp_path / "a.nc"
    with pytest.raises(InputError, match="does not exist"):
        check_output(tmp_path / "missing" / "a.nc")
    with pytest.raises(InputError, match="an existing folder"):
        check_output(tmp_path)
    with pytest.raises(InputError, match="expected a file name"):
        check_output("")


def test_output_folder_checks(tmp_path):
    (tmp_path / "f").write_text("x")
    with pytest.raises(InputError, match="an existing file; expected a folder"):
        check_output(tmp_path / "f", folder=True)
    with pytest.raises(InputError, match="is a file; expected a folder"):
        check_output(tmp_path / "f" / "sub", folder=True)
    assert check_output(tmp_path / "new" / "deeper", folder=True).name == "deeper"


@pytest.mark.skipif(os.geteuid() == 0, reason="root writes into read-only folders")
def test_a_read_only_folder(tmp_path):
    ro = tmp_path / "ro"
    ro.mkdir()
    ro.chmod(0o500)
    with pytest.raises(InputError, match="not writable"):
        check_output(ro / "out", folder=True)


def test_job_and_grid_limits():
    check_job_size(10, "x")
    with pytest.raises(ResourceError, match=r"10000001 cases \(about 1.39 h at 0.0005 s each\)"):
        check_job_size(10_000_001, "track", seconds_each=5e-4)
    check_job_size(10_000_001, "track", allow_large=True)
    check_grid_size((500, 500))
    assert MAX_GRID_ELEMENTS == 250_000
    with pytest.raises(ResourceError, match=r"4000000 elements \(about 3.2 GB"):
        check_grid_size((2000, 2000))


@pytest.mark.skipif(not os.path.isdir("/proc"), reason="needs /proc")
def test_a_place_no_file_can_be_created_in():
    """/proc refuses new files even to root: tried, not only asked of os.access."""
    with pytest.raises(InputError, match="not writable"):
        check_output("/proc/r.nc")
    with pytest.raises(InputError, match="is not writable"):
        check_output("/proc/out", folder=True)
