"""Input validation of `simulate`, `linearize`, `compare` and system files: input CSVs cell by
cell, input NPY files, reading time linear in the rows, parameter types, inputs given as
parameters, tolerances, the solver's fixed step; and the safety net that turns a bug into one
line (exit 70)."""
from __future__ import annotations

import time

import numpy as np
import pytest

from conftest import cli_in_process, run_cli
from cosim.fmu.simulate import input_signals

# the quick run (-m 'not slow') leaves this module out: it runs the command line in fresh processes
pytestmark = pytest.mark.slow

MODEL = "Bicycle.Bicycles.SelfStabilizing"
PADE = "Bicycle.Rider.PadeDelay"  # its order n is an Integer parameter


def _simulate(fmu, tmp_path, *args):
    out = tmp_path / "out.csv"
    return run_cli("simulate", str(fmu), "--stop-time", "1", "-o", str(out), *args), out


CSVS = {
    "nan-value": ("time,T\n0,0\n1,nan\n2,1\n", ":3: column 2 (T): 'nan' is not a finite number"),
    "inf-value": ("time,T\n0,0\n0.5,1\n1,inf\n", ":4: column 2 (T): 'inf' is not a finite number"),
    "overflow-value": ("time,T\n0,1e400\n", ":2: column 2 (T): '1e400' is not a finite number"),
    "nan-time": ("time,T\nnan,0\n", ":2: column 1 (time): 'nan' is not a finite number"),
    "text-cell": ("time,T\n0,0\n1,abc\n", ":3: column 2 (T): 'abc' is not a number"),
    "empty-cell": ("time,T\n0,\n", ":2: column 2 (T): '' is not a number"),
    "extra-column": ("time,T\n0,0\n1,1,3\n", ":3: 3 column(s), but the header has 2 (time,T)"),
    "decreasing-time": ("time,T\n1,0\n0,1\n", ":3: column 1 (time): time 0 s is before the previous row's 1 s"),
    "no-header": ("0,0\n1,1\n", ":1: expected a header row"),
    "empty-file": ("", ": the file is empty"),
    "header-only": ("time,T\n", ": no data rows after the header"),
    "blank-lines-and-comments-counted": ("time,T\n\n# a comment\n0,0\n1,x\n", ":5: column 2 (T): 'x' is not a number"),
}


@pytest.mark.parametrize("case", list(CSVS))
def test_input_csv_with_nan_inf_or_malformed_cell_names_file_row_and_column(fmus, tmp_path, case):
    text, message = CSVS[case]
    signal = tmp_path / "torque.csv"
    signal.write_text(text)
    result, out = _simulate(fmus[MODEL], tmp_path, "--input", f"T={signal}")
    assert result.returncode == 2, result.stdout + result.stderr
    assert "Traceback" not in result.stderr and "internal error" not in result.stderr
    assert f"cosim simulate: error: --input T: {signal}{message}" in result.stderr, result.stderr
    assert not out.exists()


def test_input_csv_column_named_after_the_input_is_used(fmus, tmp_path):
    """A result CSV of an earlier run serves as input: the column named T is taken."""
    signal = tmp_path / "earlier.csv"
    signal.write_text("time,phi,T\n0,5,0\n0.5,5,0\n0.5,5,2\n1,5,2\n")
    result, out = _simulate(fmus[MODEL], tmp_path, "--input", f"T={signal}", "--step", "0.1")
    assert result.returncode == 0, result.stderr
    data = np.genfromtxt(out, delimiter=",", names=True)
    assert np.all(data["phi"][data["time"] <= 0.5] == 0.0) and data["phi"][-1] != 0.0


def test_input_csv_malformed_after_plain_rows_names_its_line(fmus, tmp_path):
    """A bad cell far down a long file of plain numbers (read by numpy's parser until then) is
    named with its line, as in a short file."""
    signal = tmp_path / "long.csv"
    rows = [f"{0.001 * i:.3f},0" for i in range(5000)]
    rows[4321] = "4.321,oops"
    signal.write_text("time,T\n" + "\n".join(rows) + "\n")
    status, _, err = cli_in_process(["simulate", str(fmus[MODEL]), "--stop-time", "1", "-o", "out.csv",
                                     "--input", f"T={signal}"], tmp_path)
    assert status == 2 and f"--input T: {signal}:4323: column 2 (T): 'oops' is not a number" in err, err
    assert not (tmp_path / "out.csv").exists()


STRUCTURED = [("time", np.float64), ("T", np.float64)]
NPYS = {
    "nan-value": (np.array([[0.0, 0.0], [1.0, np.nan]]), ": row 2, column 2 (T): nan is not a finite number"),
    "inf-time": (np.array([(0.0, 0.0), (np.inf, 1.0)], dtype=STRUCTURED),
                 ": row 2, field 'time': inf is not a finite number"),
    "decreasing-time": (np.array([[0.0, 0.0], [1.0, 1.0], [0.5, 2.0]]),
                        ": row 3, column 1 (time): time 0.5 s is before the previous row's 1 s"),
    "no-time-field": (np.array([(0.0, 1.0)], dtype=[("t", np.float64), ("T", np.float64)]),
                      ": the array has the fields t, T; expected a structured array with fields 'time' and 'T'"),
    "three-columns": (np.zeros((4, 3)), ": an array of shape (4, 3) and type float64; expected"),
    "text-field": (np.array([("0", "1")], dtype=[("time", "U3"), ("T", "U3")]),
                   ": field 'time' holds <U3 values, not real numbers"),
    "no-rows": (np.zeros((0, 2)), ": the array has no rows"),
    "object-array": (np.array([None, 1.0], dtype=object), ": not a readable .npy file: Object arrays cannot be loaded"),
    "not-npy": ("time,T\n0,1\n", ": not a NumPy .npy file (it does not start with the .npy magic string"),
}


@pytest.mark.parametrize("case", list(NPYS))
def test_input_npy_with_bad_value_or_shape_names_file_row_and_field(fmus, tmp_path, case):
    data, message = NPYS[case]
    signal = tmp_path / "torque.npy"
    if isinstance(data, str):
        signal.write_text(data)
    else:
        np.save(signal, data, allow_pickle=True)
    status, _, err = cli_in_process(["simulate", str(fmus[MODEL]), "--stop-time", "1", "-o", "out.csv",
                                     "--input", f"T={signal}"], tmp_path)
    assert status == 2 and "Traceback" not in err and "internal error" not in err, err
    assert f"cosim simulate: error: --input T: {signal}{message}" in err, err
    assert not (tmp_path / "out.csv").exists()


@pytest.mark.parametrize("layout", ["two-columns", "structured", "result-with-named-field"])
def test_input_npy_gives_the_result_of_the_same_csv(fmus, tmp_path, layout):
    """The same signal as CSV and as NPY (each layout the help names) gives the same result to
    1e-15 rad: the values are read as float64 either way."""
    t = np.array([0.0, 0.3, 0.3, 1.0])
    torque = np.array([0.0, 0.5, 1.5, -1.0])
    (tmp_path / "in.csv").write_text("time,T\n" + "".join(f"{a:.17g},{b:.17g}\n" for a, b in zip(t, torque)))
    if layout == "two-columns":
        data = np.column_stack([t, torque])
    elif layout == "structured":
        data = np.array(list(zip(t, torque)), dtype=STRUCTURED)
    else:  # a result of an earlier run: time, other outputs, the input's column by name
        data = np.array(list(zip(t, 5 * torque, torque)), dtype=[("time", float), ("phi", float), ("T", float)])
    np.save(tmp_path / "in.npy", data)
    runs = {}
    for name in ("in.csv", "in.npy"):
        status, _, err = cli_in_process(["simulate", str(fmus[MODEL]), "--stop-time", "1", "--step", "0.1",
                                         "--input", f"T={name}", "-o", f"{name}.out.csv"], tmp_path)
        assert status == 0, err
        runs[name] = np.genfromtxt(tmp_path / f"{name}.out.csv", delimiter=",", names=True)
    assert np.max(np.abs(runs["in.csv"]["phi"])) > 1e-4  # the torque moved the bicycle
    np.testing.assert_allclose(runs["in.npy"]["phi"], runs["in.csv"]["phi"], rtol=0, atol=1e-15)


def _input_files(folder, rows: int) -> dict:
    """An input of ``rows`` rows as plain CSV, as CSV with a comment line (read row by row) and
    as NPY."""
    t = np.linspace(0.0, 1.0, rows)
    data = np.column_stack([t, np.sin(7.0 * t)])
    files = {"csv": folder / f"plain{rows}.csv", "csv-checked-rows": folder / f"commented{rows}.csv",
             "npy": folder / f"in{rows}.npy"}
    np.savetxt(files["csv"], data, delimiter=",", header="time,T", comments="", fmt="%.17g")
    header, _, body = files["csv"].read_text().partition("\n")
    files["csv-checked-rows"].write_text(f"{header}\n# a comment\n{body}")
    np.save(files["npy"], data)
    return files


@pytest.mark.parametrize("kind", ["csv", "csv-checked-rows", "npy"])
def test_reading_inputs_takes_time_linear_in_the_rows(fmus, tmp_path, kind):
    """`input_signals`, what `simulate --input` runs, on 2e5 rows takes at most 30 times as long
    as on 2e4 rows (linear: about 10; quadratic: about 100), both measured here, best of 3; and
    gives FMPy's array of every row."""
    files = {rows: _input_files(tmp_path, rows)[kind] for rows in (20_000, 200_000)}
    best = {}
    for rows, path in files.items():
        times = []
        for _ in range(3):
            started = time.perf_counter()
            signals = input_signals(fmus[MODEL], [f"T={path}"], 0.0, 1.0)
            times.append(time.perf_counter() - started)
        assert len(signals) == rows and signals["T"][-1] == pytest.approx(np.sin(7.0), rel=1e-15)
        best[rows] = min(times)
    assert best[200_000] < 30 * best[20_000], best


@pytest.mark.parametrize("target", ["fmu", "model"])
def test_integer_parameter_given_non_integer_is_refused(fmus, tmp_path, target):
    fmu = fmus[PADE] if target == "fmu" else PADE
    result, out = _simulate(fmu, tmp_path, "--param", "n=2.5")
    assert result.returncode == 2 and "Traceback" not in result.stderr
    assert "parameter 'n' is an Integer; 2.5 is not a whole number" in result.stderr, result.stderr
    assert not out.exists()
    result, out = _simulate(fmu, tmp_path, "--param", "n=2")  # a whole number is fine
    assert result.returncode == 0, result.stderr


def test_integer_parameter_in_system_file_is_checked(fmus, tmp_path):
    system = tmp_path / "s.toml"
    system.write_text(f'connections = []\n[components.delay]\nfmu = "{fmus[PADE]}"\nparameters = {{ n = 2.5 }}\n')
    result = run_cli("run", str(system), "-o", str(tmp_path / "r.csv"))
    assert result.returncode == 2
    assert "component 'delay': parameter 'n' is an Integer; 2.5 is not a whole number" in result.stderr


@pytest.mark.parametrize("target", ["fmu", "model"])
def test_param_given_an_input_is_refused_naming_input_option(fmus, tmp_path, target):
    fmu = fmus[MODEL] if target == "fmu" else MODEL
    result, out = _simulate(fmu, tmp_path, "--param", "T=1")
    assert result.returncode == 2 and "Traceback" not in result.stderr
    assert "'T' is an input, not a parameter; give it with --input T=FILE.csv or --input T=step:T0:VALUE" \
        in result.stderr, result.stderr
    assert not out.exists()


def test_linearize_param_given_an_input_points_to_its_input_option(fmus):
    result = run_cli("linearize", str(fmus[MODEL]), "--param", "T=1")
    assert result.returncode == 2 and "give its operating-point value with --input T=VALUE" in result.stderr
    result = run_cli("linearize", str(fmus[MODEL]), "--input", "T=0.5", "--speed", "6", "--json")
    assert result.returncode == 0, result.stderr


def test_system_parameter_given_an_input_is_refused(fmus, tmp_path):
    system = tmp_path / "s.toml"
    system.write_text(f'connections = []\n[components.bike]\nfmu = "{fmus[MODEL]}"\nparameters = {{ T = 1.0 }}\n')
    result = run_cli("run", str(system), "-o", str(tmp_path / "r.csv"))
    assert result.returncode == 2
    assert "component 'bike': 'T' is an input, not a parameter; connect it" in result.stderr


@pytest.mark.parametrize("tol", ["-1", "0", "nan", "inf"])
def test_compare_nonpositive_or_nonfinite_tol_is_refused(tol):
    result = run_cli("compare", MODEL, "--tol", tol)
    assert result.returncode == 2 and "Traceback" not in result.stderr
    assert "--tol" in result.stderr and ("must be > 0" in result.stderr or "must be finite" in result.stderr)
    assert "largest relative error" not in result.stdout  # refused before any linearization


@pytest.mark.parametrize("speeds", ["1:a", "1:2", "1:9:0", "nan,1", "1:1e9:1e-9"])
def test_compare_malformed_speeds_are_refused(speeds):
    result = run_cli("compare", MODEL, "--speeds", speeds)
    assert result.returncode == 2 and "--speeds" in result.stderr
    assert "Traceback" not in result.stderr and "internal error" not in result.stderr, result.stderr


@pytest.mark.parametrize("target", ["fmu", "model"])
def test_solver_fixed_step_size_is_validated_by_model_name_and_by_fmu(fmus, tmp_path, target):
    fmu = fmus[MODEL] if target == "fmu" else MODEL
    for value, message in (("-0.01", "parameter 'solver.fixedStepSize' = -0.01 s is below its minimum 0 s"),
                           ("inf", "parameter 'solver.fixedStepSize': value must be finite"),
                           ("x", "parameter 'solver.fixedStepSize': 'x' is not a number")):
        result, out = _simulate(fmu, tmp_path, "--param", f"solver.fixedStepSize={value}")
        assert result.returncode == 2 and message in result.stderr, result.stderr
        assert not out.exists()
    result, out = _simulate(fmu, tmp_path, "--param", "solver.fixedStepSize=0.001", "--fmi-type", "me")
    assert result.returncode == 2 and "with --fmi-type me FMPy's CVode integrates" in result.stderr


def test_solver_fixed_step_size_is_applied(fmus, tmp_path):
    """The fixed step is used: fixed steps of 0.5 s differ from fixed steps of 1 ms by their
    truncation error, while the error-controlled solver (tolerance 1e-8) agrees with 1 ms steps."""
    signal = ["--input", "T=step:0.5:1", "--param", "V=6", "--step", "0.5"]
    runs = {}
    for h in ("0", "0.5", "0.001"):
        out = tmp_path / f"h{h}.csv"
        result = run_cli("simulate", str(fmus[MODEL]), "--stop-time", "4", *signal,
                         "--param", f"solver.fixedStepSize={h}", "-o", str(out))
        assert result.returncode == 0, result.stderr
        runs[h] = np.genfromtxt(out, delimiter=",", names=True)["phi"]
    coarse = float(np.max(np.abs(runs["0.5"] - runs["0.001"])))
    adaptive = float(np.max(np.abs(runs["0"] - runs["0.001"])))
    assert coarse > 1e-6 and adaptive < 1e-8, (coarse, adaptive)


def test_unexpected_exception_is_one_line_internal_error_exit_70(monkeypatch, capsys):
    from cosim import cli
    from cosim.fmu import info

    def broken(*args, **kwargs):
        raise ZeroDivisionError("a bug\nover two lines")

    monkeypatch.setattr(info, "describe_target", broken)
    monkeypatch.delenv("COSIM_DEBUG", raising=False)
    assert cli.main(["info", MODEL]) == 70
    err = capsys.readouterr().err
    assert err == ("cosim info: internal error: ZeroDivisionError: a bug over two lines "
                   "(set COSIM_DEBUG=1 for the traceback)\n")
    monkeypatch.setenv("COSIM_DEBUG", "1")
    assert cli.main(["info", MODEL]) == 70
    err = capsys.readouterr().err
    assert "Traceback (most recent call last)" in err and err.rstrip().endswith("for the traceback)")


def test_help_states_exit_codes_and_fmu_folder():
    result = run_cli("--help")
    assert result.returncode == 0
    for text in ("0    success", "2    bad input", "3    run: the bicycle fell", "4    incomplete result",
                 "70   internal error", "./fmus of the", "COSIM_FMU_DIR"):
        assert text in result.stdout, text
    for verb, text in (("simulate", "solver.fixedStepSize"), ("simulate", "NAME.incomplete.csv"),
                       ("run", "the last step is the shorter remainder")):
        assert text in " ".join(run_cli(verb, "--help").stdout.split()), (verb, text)
