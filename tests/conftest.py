"""Shared fixtures and helpers: FMUs are built once per test session into a temporary folder;
every temporary and cache file of the session goes into one folder removed at exit."""
from __future__ import annotations

import atexit
import ctypes
import functools
import importlib.util
import os
import pickle
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

# Everything the suite and the processes it starts write to temporary or cache folders goes into one
# session folder, removed at exit: FMU extraction folders (also those of processes the kill tests end
# with SIGKILL, which never run their atexit), pytest's tmp_path base, the compiled C stepping loop,
# pymoca's parse cache and matplotlib's font cache. Nothing is left in /tmp or ~. Set before cosim is
# imported; subprocesses inherit the environment. To keep the tmp_path folders of a failed run, give
# pytest --basetemp=DIR.
#
# Under pytest-xdist the workers share the folder of the process that started them (it is in their
# inherited environment): the FMUs, the compiled runtime and Zig's C library are built once per run,
# not once per worker (concurrent builds of one FMU wait for each other, see cosim.compiler.build).
# The starting process alone removes it.
if os.environ.get("PYTEST_XDIST_WORKER") and os.environ.get("COSIM_TEST_SESSION_TMP"):
    SESSION_TMP = Path(os.environ["COSIM_TEST_SESSION_TMP"])
else:
    SESSION_TMP = Path(tempfile.mkdtemp(prefix="cosim-tests-"))
    atexit.register(shutil.rmtree, SESSION_TMP, True)
    for _variable, _folder in (("TMPDIR", "tmp"), ("XDG_CACHE_HOME", "cache"), ("MPLCONFIGDIR", "matplotlib")):
        (SESSION_TMP / _folder).mkdir()
        os.environ[_variable] = str(SESSION_TMP / _folder)
    os.environ["COSIM_TEST_SESSION_TMP"] = str(SESSION_TMP)
tempfile.tempdir = None  # tempfile caches its folder: make it read TMPDIR again

# FMUs built on demand (model names given to the CLI, figures, systems) go to a temporary folder,
# never into the project's fmus/. A developer may name a folder that is kept between runs
# (COSIM_TEST_FMU_DIR): builds are incremental, so reusing it is safe.
if os.environ.get("COSIM_TEST_FMU_DIR"):
    os.environ["COSIM_FMU_DIR"] = os.environ["COSIM_TEST_FMU_DIR"]
else:
    os.environ["COSIM_FMU_DIR"] = str(SESSION_TMP / "fmus")

# Where PYTHONDONTWRITEBYTECODE is set (as on some CI images) Python writes no bytecode, so every
# `python -m cosim` the tests start would compile the package's modules again: 20-60 ms a process,
# about a minute of CPU over the suite. The starting process writes the package's bytecode once,
# beside its sources, where Python puts it by default (nothing is written where the folder is
# read-only); the test processes write theirs, the rewritten test modules, as pytest does by default.
sys.dont_write_bytecode = False
if not os.environ.get("PYTEST_XDIST_WORKER"):
    import compileall

    compileall.compile_dir(importlib.util.find_spec("cosim").submodule_search_locations[0], quiet=2)

import numpy as np  # noqa: E402
import pytest  # noqa: E402

try:  # hypothesis' example database and caches (else .hypothesis/ in the working directory)
    from hypothesis.configuration import set_hypothesis_home_dir

    set_hypothesis_home_dir(SESSION_TMP / "hypothesis")
except ImportError:
    pass

from cosim.compiler.build import build  # noqa: E402
from cosim.compiler.library import DEFAULT_LIBRARY, Library  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]


@functools.cache
def shipped_models(exported_only: bool = False) -> list[str]:
    """The names of the shipped library's models (those `cosim build` exports), from one parse per
    process: several test modules parametrize over them at collection."""
    return [e.name for e in Library(DEFAULT_LIBRARY).models(exported_only=exported_only)]


@pytest.fixture(scope="session")
def fmus() -> dict[str, Path]:
    """Every exported model built from the project's Modelica library: name -> FMU path (into the
    temporary COSIM_FMU_DIR, where on-demand builds of the same models then find them)."""
    return {r.model: r.fmu for r in build(output=os.environ["COSIM_FMU_DIR"], jobs=2)}


def unavailable(reason: str):
    """Skip with the reason on a developer's machine; fail in CI, which must have everything."""
    if os.environ.get("CI"):
        pytest.fail(f"{reason} (CI must install it: see .ci/run)")
    pytest.skip(reason)


@pytest.fixture(scope="session")
def app_site(tmp_path_factory) -> Path:
    """`cosim app --export` into a temporary folder, once per session (its FMUs and WebAssembly
    modules into COSIM_FMU_DIR): the site every test of the page opens; none may change it."""
    if importlib.util.find_spec("ziglang") is None:
        unavailable("the ziglang wheel is not installed (pip install ziglang)")
    folder = tmp_path_factory.mktemp("app") / "site"
    status, out, err = cli_in_process(["app", "--export", str(folder)], folder.parent)
    assert status == 0, err
    assert sorted(p.name for p in folder.iterdir()) == ["bundle.js", "index.html"]
    return folder


def bundle_data(site: Path) -> dict:
    """``window.COSIM_DATA`` of the bundle.js that `cosim app --export` wrote into ``site``."""
    import json
    import re

    text = (site / "bundle.js").read_text(encoding="utf-8")
    return json.loads(re.search(r"^window\.COSIM_DATA = (.*);$", text, re.M).group(1))


def variant_library(folder: Path, models: dict[str, str], package: str = "TestVariants"):
    """The project's library plus a package ``package`` in ``folder`` holding ``models`` (class name ->
    Modelica text of the class, e.g. ``model V extends Bicycle.Bicycles.Whipple(redeclare ...); end V;``),
    as one :class:`~cosim.compiler.library.Library` of two folders: variants are built as
    ``PACKAGE.NAME`` without copying the library."""
    from cosim.compiler.library import Library

    root = folder / package
    root.mkdir(parents=True)
    (root / "package.mo").write_text(f"within;\npackage {package} \"Test variants\"\nend {package};\n", encoding="utf-8")
    (root / "package.order").write_text("".join(f"{name}\n" for name in models), encoding="utf-8")
    for name, text in models.items():
        (root / f"{name}.mo").write_text(f"within {package};\n{text.strip()}\n", encoding="utf-8")
    return Library([ROOT / "modelica", folder])


def hide_shipped_library(folder: Path) -> Path:
    """Give the library folder ``folder`` a package ``Bicycle`` of its own, which hides the shipped
    one (the first folder holding a top-level package wins, as with MODELICAPATH): tests of a small
    library then neither parse nor list nor build the shipped library, which is always searched
    after the user's folders. Returns ``folder``."""
    (folder / "Bicycle").mkdir(parents=True)
    (folder / "Bicycle" / "package.mo").write_text('within;\npackage Bicycle "hides the shipped library"\n'
                                                   'end Bicycle;\n', encoding="utf-8")
    return folder


def calculated_parameters(fmu_path, names, parameters=None) -> dict:
    """Values of (calculated) parameters read in initialization mode."""
    from cosim.fmu.access import FMU

    with FMU(fmu_path) as f:
        me = f.instantiate("me")
        f.set(me, parameters or {})
        me.setupExperiment(startTime=0.0)
        me.enterInitializationMode()
        values = dict(zip(names, f.get_real(me, list(names))))
        me.exitInitializationMode()
        me.terminate()
        me.freeInstance()
    return values


def failing_do_step(monkeypatch, status: int, from_time: float, terminated: list | None = None) -> None:
    """Every FMU component's fmi2DoStep returns ``status`` (2 Discard, 3 Error) from ``from_time``
    [s] on, in the C stepping loop and in the Python one; ``terminated`` (if given) collects the
    names of the components whose fmi2Terminate is called."""
    from ctypes import CFUNCTYPE, c_double, c_int, c_void_p

    from cosim.cosimulation.component import FMUComponent

    original_setup = FMUComponent.setup

    def setup_with_failing_step(self, start_time):
        original_setup(self, start_time)
        real = self._do_step

        @CFUNCTYPE(c_int, c_void_p, c_double, c_double, c_int)
        def do_step(component, t, h, no_prior):
            return status if t >= from_time - 1e-9 else real(component, t, h, no_prior)

        self._keep_alive, self._do_step = do_step, do_step
        if terminated is not None:
            instance, terminate = self.instance, self.instance.terminate
            instance.terminate = lambda: (terminated.append(self.name), terminate())[1]

    monkeypatch.setattr(FMUComponent, "setup", setup_with_failing_step)


def run_cli(*args: str, cwd: Path | None = None, env: dict | None = None) -> subprocess.CompletedProcess:
    """Run `python -m cosim ...` as a user would, capturing its output."""
    environment = {**os.environ, **(env or {})}
    return subprocess.run([sys.executable, "-m", "cosim", *args], capture_output=True, text=True,
                          cwd=cwd or ROOT, env=environment, timeout=600)


#: The capabilities that let root ignore permission bits: CAP_DAC_OVERRIDE, CAP_DAC_READ_SEARCH.
_PERMISSION_OVERRIDES = (1, 2)
_PR_CAPBSET_DROP = 24
_CAPABILITY_VERSION_3 = 0x20080522


class _CapabilityHeader(ctypes.Structure):
    _fields_ = [("version", ctypes.c_uint32), ("pid", ctypes.c_int)]


class _CapabilityData(ctypes.Structure):
    _fields_ = [("effective", ctypes.c_uint32), ("permitted", ctypes.c_uint32), ("inheritable", ctypes.c_uint32)]


def _drop_permission_overrides() -> None:
    """Make this process bound by permission bits, as root too: the capabilities that override them
    leave the effective, permitted and inheritable sets, and the bounding set, so that programs it
    runs do not get them back at exec (root's exec grants the bounding set). Without them a folder
    of mode 0o555 is as read-only for root as it is for every other user."""
    libc = ctypes.CDLL(None, use_errno=True)
    for capability in _PERMISSION_OVERRIDES:
        if libc.prctl(_PR_CAPBSET_DROP, capability, 0, 0, 0) != 0 and os.geteuid() == 0:
            raise OSError(ctypes.get_errno(), f"prctl(PR_CAPBSET_DROP, {capability})")
    header, data = _CapabilityHeader(_CAPABILITY_VERSION_3, 0), (_CapabilityData * 2)()
    if libc.capget(ctypes.byref(header), data) != 0:
        raise OSError(ctypes.get_errno(), "capget")
    keep = ~sum(1 << capability for capability in _PERMISSION_OVERRIDES) & 0xFFFFFFFF
    for name in ("effective", "permitted", "inheritable"):
        setattr(data[0], name, getattr(data[0], name) & keep)
    if libc.capset(ctypes.byref(header), data) != 0:
        raise OSError(ctypes.get_errno(), "capset")


def bound_by_permissions(operation, locked: Path):
    """``operation()`` in a forked child bound by permission bits (root without the capabilities
    that override them; an ordinary user as it is), after checking that the child cannot create a
    file in the folder ``locked``: the barrier holds for whoever runs the suite, root included (CI).
    Returns what ``operation`` returns; re-raises what it raises (assertions included)."""
    read, write = os.pipe()
    pid = os.fork()
    if pid == 0:  # the child: never returns into pytest, runs no atexit (the session folder stays)
        try:
            os.close(read)
            _drop_permission_overrides()
            try:
                (locked / "probe").touch()
                outcome = ("raised", AssertionError(f"the barrier does not hold: {locked} is writable"))
            except PermissionError:
                outcome = ("returned", operation())
        except BaseException as error:  # noqa: BLE001 - everything goes back to the test
            outcome = ("raised", error)
        try:
            message = pickle.dumps(outcome)
        except Exception:  # noqa: BLE001 - an outcome that does not pickle is reported as text
            message = pickle.dumps(("raised", AssertionError(repr(outcome))))
        with os.fdopen(write, "wb") as pipe:
            pipe.write(message)
        os._exit(0)
    os.close(write)
    with os.fdopen(read, "rb") as pipe:
        message = pipe.read()
    _, status = os.waitpid(pid, 0)
    assert message, f"the child bound by permissions ended without an outcome (wait status {status})"
    kind, value = pickle.loads(message)
    if kind == "raised":
        raise value
    return value


def cli_in_process(argv: list[str], cwd: Path) -> tuple[int, str, str]:
    """``cosim ARGV`` in this process, in ``cwd``: (exit status, stdout, stderr). Faster than
    :func:`run_cli` for the many small calls of the bad-input tests."""
    import contextlib
    import io

    from cosim.cli import main

    out, err = io.StringIO(), io.StringIO()
    here = os.getcwd()
    os.chdir(cwd)
    try:
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            try:
                status = main(list(argv))
            except SystemExit as exc:  # argparse usage errors exit 2
                status = exc.code if isinstance(exc.code, int) else 2
    finally:
        os.chdir(here)
    return status, out.getvalue(), err.getvalue()


def pytest_collection_modifyitems(config, items):
    """Under pytest-xdist, the modules with a slow test first and the quick modules last, each
    module's tests together and in their order: the workers take whole modules in this order
    (``--dist loadfile``), so the many short tests fill both workers at the end instead of a long
    module running alone on one of them while the other waits. One process runs in file order."""
    if not os.environ.get("PYTEST_XDIST_WORKER"):
        return
    slow = {item.path for item in items if item.get_closest_marker("slow") is not None}
    items.sort(key=lambda item: item.path not in slow)  # stable: the order within each group


@pytest.hookimpl(wrapper=True)
def pytest_runtest_call(item):
    """A test that needs an independent FMI engine which cannot be loaded here is skipped with
    the reason (e.g. Ecos without libtbb.so.12), not failed: one clear line in the summary.
    tests/test_engines.py fails instead when the test extra is installed and an engine still
    does not load."""
    from cosim.engines import EngineUnavailable

    try:
        return (yield)
    except EngineUnavailable as exc:
        pytest.skip(str(exc))


def png_pixels(path: Path) -> np.ndarray:
    """The RGB pixels (height x width x 3, floats 0..1) of a PNG file, refusing anything else."""
    import matplotlib.image
    import numpy as np

    data = Path(path).read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n", f"{path} is not a PNG"
    return np.asarray(matplotlib.image.imread(path))[..., :3]


def line_pixels(path: Path, color: str = "C0") -> int:
    """How many pixels of the PNG at ``path`` have the colour of a matplotlib line (default: the
    first line colour, C0): 0 means no such line was drawn."""
    import matplotlib.colors
    import numpy as np

    rgb = np.asarray(matplotlib.colors.to_rgb(color))
    return int((np.abs(png_pixels(path) - rgb).max(axis=-1) < 0.05).sum())


@pytest.fixture()
def drawn_figures(monkeypatch) -> list:
    """Every matplotlib figure saved during the test, with what its axes show, recorded at save
    time: a list of ``(path, [per axes: list of (x, y) arrays of its lines and point sets],
    readability)``, ``readability`` as :func:`readability` finds it."""
    import matplotlib.figure
    import numpy as np

    saved = []
    original = matplotlib.figure.Figure.savefig

    def record(fig, fname, *args, **kwargs):
        axes = []
        for ax in fig.axes:
            if hasattr(ax, "_colorbar"):
                continue  # a colour bar shows a scale, not data
            data = [(np.asarray(line.get_xdata(), float), np.asarray(line.get_ydata(), float))
                    for line in ax.get_lines()]
            data += [(c.get_offsets()[:, 0], c.get_offsets()[:, 1]) for c in ax.collections
                     if len(c.get_offsets()) > 1]
            axes.append(data)
        saved.append((fname, axes, readability(fig)))
        return original(fig, fname, *args, **kwargs)

    monkeypatch.setattr(matplotlib.figure.Figure, "savefig", record)
    return saved


def readability(fig) -> dict:
    """What a reader meets in a drawn figure: ``"unlabelled"``, the axes sides (``"axes 0 y:
    'phi'"``) that show tick labels without a ``[unit]`` in their label, ``"covered"``, per
    legend the data points it lies on (``"legend 'a, b' over 3 points of axes 0"``); and the
    ``"ylabels"``, ``"legend"`` texts, ``"colorbars"`` labels and ``"colormaps"`` of the cells.

    Data points: each line drawn in data coordinates, sampled 20 times per segment in display
    coordinates, and each point set; reference lines across the axes (axhline, grid) are not data.
    Inset axes (children of another axes) are read as part of their parent.
    """
    import re

    import numpy as np
    from matplotlib.collections import PathCollection

    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    insets = {id(child) for ax in fig.axes for child in ax.child_axes}
    shown = [ax for ax in fig.axes if not hasattr(ax, "_colorbar") and id(ax) not in insets]
    unlabelled = []
    for k, ax in enumerate(shown):
        for side, ticks, label in (("x", ax.get_xticklabels(), ax.get_xlabel()),
                                   ("y", ax.get_yticklabels(), ax.get_ylabel())):
            if any(t.get_visible() and t.get_text() for t in ticks) and not re.search(r"\[[^\]]+\]", label):
                unlabelled.append(f"axes {k} {side}: {label!r}")
    points = []
    for k, ax in enumerate(shown):
        for line in ax.get_lines():
            if line.get_transform() != ax.transData or not line.get_visible():
                continue
            xy = ax.transData.transform(np.column_stack([line.get_xdata(), line.get_ydata()]).astype(float))
            if line.get_linestyle() not in ("None", "none", "", " ") and len(xy) > 1:
                t = np.linspace(0.0, 1.0, 20)[None, :, None]
                xy = (xy[:-1, None, :] + t * (xy[1:] - xy[:-1])[:, None, :]).reshape(-1, 2)
            points.append((k, xy[np.all(np.isfinite(xy), axis=1)]))
        for c in ax.collections:
            if len(c.get_offsets()) > 1 and c.get_offset_transform() == ax.transData:
                xy = ax.transData.transform(np.asarray(c.get_offsets(), float))
                points.append((k, xy[np.all(np.isfinite(xy), axis=1)]))
    legends = [ax.get_legend() for ax in shown if ax.get_legend() is not None] + list(fig.legends)
    covered = []
    for legend in legends:
        box = legend.get_window_extent(renderer)
        for k, xy in points:
            inside = ((xy[:, 0] >= box.x0) & (xy[:, 0] <= box.x1) & (xy[:, 1] >= box.y0) & (xy[:, 1] <= box.y1))
            if inside.any():
                names = ", ".join(t.get_text() for t in legend.get_texts())
                covered.append(f"legend {names[:60]!r} over {int(inside.sum())} points of axes {k}")
    return {"unlabelled": unlabelled, "covered": covered, "ylabels": [ax.get_ylabel() for ax in shown],
            "legend": [t.get_text() for legend in legends for t in legend.get_texts()],
            "colorbars": [ax.get_xlabel() or ax.get_ylabel() for ax in fig.axes if hasattr(ax, "_colorbar")],
            "colormaps": [c.cmap for ax in shown for c in ax.collections
                          if isinstance(c, PathCollection) and c.get_array() is not None]}


def assert_readable(record: tuple) -> None:
    """A figure recorded by :func:`drawn_figures` has a unit on every labelled axis side and no
    legend over its data (:func:`readability`)."""
    path, _, found = record
    assert not found["unlabelled"], f"{path}: axes without a unit: {found['unlabelled']}"
    assert not found["covered"], f"{path}: {found['covered']}"


def assert_plotted(axes_data: list, min_points: int = 10) -> None:
    """Each axes shows at least one curve or point set of ``min_points`` finite points that is
    not constant (an empty or all-NaN axes, or only reference lines, fails)."""
    import numpy as np

    assert axes_data, "the figure has no axes"
    for i, data in enumerate(axes_data):
        curves = [(x, y) for x, y in data if np.isfinite(x).sum() >= min_points and np.isfinite(y).sum() >= min_points
                  and np.nanmax(y) > np.nanmin(y)]
        assert curves, f"axes {i} shows no curve of {min_points} finite, varying points"


def toml_value(value) -> str:
    """A Python value (bool, int, float incl. nan/inf, str, list, dict) as a TOML value, for tests
    that write system files and specs."""
    import json
    import math

    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float) and not math.isfinite(value):
        return "nan" if math.isnan(value) else ("inf" if value > 0 else "-inf")
    if isinstance(value, (int, float, str)):
        return json.dumps(value)  # JSON numbers and strings are TOML ones
    if isinstance(value, list):
        return "[" + ", ".join(toml_value(v) for v in value) + "]"
    if isinstance(value, dict):
        return "{" + ", ".join(f"{json.dumps(str(k))} = {toml_value(v)}" for k, v in value.items()) + "}"
    raise TypeError(value)
