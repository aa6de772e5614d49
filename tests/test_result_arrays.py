"""FMI 3 array variables in a result file: one CSV column per value, one unique name per column.

FMPy records an array variable (an FMI 3 variable with dimensions) as one field of its shape. The
CSV writer flattens it row-major to ``y[1]``, ``y[2]``, ... (``A[1,1]``, ``A[1,2]``, ... for more
dimensions, 1-based), so that ``fmpy.util.read_csv`` and ``numpy.genfromtxt`` read the file back;
NPY keeps the structured array with its subarray fields. The Reference FMU ``StateSpace`` (FMI 3,
an output vector ``y`` of 3, tests/reference_fmus.py) is simulated and read back.
"""
from __future__ import annotations

import csv

import numpy as np
import pytest

from conftest import cli_in_process
from cosim.fmu.simulate import write_csv, write_result
from reference_fmus import reference_fmu

STOP, STEP = 1.0, 0.05  # s


@pytest.fixture(scope="module")
def state_space(tmp_path_factory):
    return reference_fmu("StateSpace", tmp_path_factory.mktemp("state-space"))


@pytest.mark.parametrize("fmi_type", ["cs", "me"])
def test_state_space_csv_reads_back_as_fmpy_result(state_space, tmp_path, fmi_type):
    from fmpy import simulate_fmu
    from fmpy.util import read_csv

    out = tmp_path / "ss.csv"
    code, stdout, stderr = cli_in_process(["simulate", str(state_space), "--stop-time", str(STOP), "--step", str(STEP),
                                           "--fmi-type", fmi_type, "-o", str(out)], tmp_path)
    assert code == 0, stdout + stderr
    header = out.read_text().splitlines()[0].split(",")
    assert header == ["time", "y[1]", "y[2]", "y[3]"] and len(set(header)) == len(header)
    ours = read_csv(out)
    theirs = simulate_fmu(str(state_space), stop_time=STOP, output_interval=STEP, output=["y"],
                          fmi_type="CoSimulation" if fmi_type == "cs" else "ModelExchange")
    assert len(ours) == len(theirs) == round(STOP / STEP) + 1
    np.testing.assert_array_equal(ours["time"], theirs["time"])
    for i in range(3):
        np.testing.assert_array_equal(ours[f"y[{i + 1}]"], theirs["y"][:, i])
    assert np.ptp(theirs["y"][:, 2]) > 1.0  # the outputs move: the comparison is not of constants


def _recorded(rows: int = 4) -> np.ndarray:
    """A result as FMPy's recorder builds it: time, a scalar, a vector of 3 and a 2 x 3 matrix."""
    dtype = [("time", np.float64), ("k", np.float64), ("y", np.float64, (3,)), ("A", np.float64, (2, 3))]
    result = np.zeros(rows, dtype=dtype)
    result["time"] = np.linspace(0.0, 0.3, rows)
    result["k"] = np.arange(rows) / 7.0
    result["y"] = np.arange(rows * 3).reshape(rows, 3) / 3.0
    result["A"] = np.arange(rows * 6).reshape(rows, 2, 3) * 0.1
    return result


def test_vector_columns_read_back_with_fmpy(tmp_path):
    from fmpy.util import read_csv

    result = _recorded()[["time", "k", "y"]]
    path = write_csv(result, tmp_path / "r.csv")
    header = path.read_text().splitlines()[0].split(",")
    assert header == ["time", "k", "y[1]", "y[2]", "y[3]"]
    back = read_csv(path)
    np.testing.assert_array_equal(back["time"], result["time"])
    np.testing.assert_array_equal(back["k"], result["k"])
    for i in range(3):  # the round trip through "%.17g" is exact
        np.testing.assert_array_equal(back[f"y[{i + 1}]"], result["y"][:, i])


def test_matrix_columns_row_major_one_based_unique(tmp_path):
    result = _recorded()
    path = write_csv(result, tmp_path / "r.csv")
    with open(path, newline="") as file:
        rows = list(csv.reader(file))
    header, values = rows[0], np.array(rows[1:], dtype=float)
    assert header[5:] == ["A[1,1]", "A[1,2]", "A[1,3]", "A[2,1]", "A[2,2]", "A[2,3]"]
    assert len(set(header)) == len(header) == values.shape[1] == 1 + 1 + 3 + 6
    np.testing.assert_array_equal(values[:, 5:], result["A"].reshape(len(result), 6))
    np.testing.assert_array_equal(values[:, header.index("A[2,1]")], result["A"][:, 1, 0])


@pytest.mark.parametrize("rows", [0, 1], ids=["empty", "one-row"])
def test_few_rows_keep_every_column(tmp_path, rows):
    path = write_csv(_recorded(rows), tmp_path / "r.csv")
    lines = path.read_text().splitlines()
    assert len(lines) == 1 + rows
    assert all(len(next(csv.reader([line]))) == 11 for line in lines)


def test_npy_keeps_the_array_fields(tmp_path):
    result = _recorded()
    back = np.load(write_result(result, tmp_path / "r.npy"))
    assert back.dtype == result.dtype and back["A"].shape == (len(result), 2, 3)
    np.testing.assert_array_equal(back["A"], result["A"])
