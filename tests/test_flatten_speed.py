"""The speed-ups of flattening change nothing but the time.

- cosim/compiler/pymoca_walker.py: the fast tree walk makes the same listener calls, in the same
  order, as pymoca's own walk, for pymoca's TreeWalker and the CasADi backend's GeneratorWalker;
- cosim/compiler/pymoca_patches.py (``_full_scope_once``): the full instances of unnamed scopes
  kept for a whole flattening give the same flat model as instances made per symbol, and a scope
  pymoca changes is instantiated afresh;
- cosim/compiler/schedule.py: a parallel build starts the longest models first and keeps no
  more than a hint.
"""
from __future__ import annotations

import contextlib
import json

import pytest

from cosim.compiler import pymoca_patches, schedule
from cosim.compiler.build import _fingerprint
from cosim.compiler.flatten import flatten
from cosim.compiler.library import load_library

# the quick run (-m 'not slow') leaves this module out: it builds FMUs from Modelica per test
pytestmark = pytest.mark.slow

MODELS = ["Bicycle.Bicycles.WhippleRider", "Bicycle.Bicycles.WhippleLinear", "Bicycle.Bicycles.SelfStabilizing",
          "Bicycle.Control.PID"]


def _recording_listener():
    """A listener that records every enter/exit call (class name, node identity), and the
    context that TreeListener.enterEvery keeps, at each call."""
    from pymoca.tree import TreeListener

    calls = []

    def recorder(name):
        def method(self, tree):
            calls.append((name, id(tree), type(tree).__name__, tuple(sorted(self.context))))
        return method

    names = [n for n in vars(TreeListener) if n.startswith(("enter", "exit")) and n not in ("enterEvery", "exitEvery")]
    # half the methods recorded, half left as the base class's no-ops (which the fast walk skips)
    recorded = {n: recorder(n) for i, n in enumerate(sorted(names)) if i % 2 == 0}
    listener_class = type("Recorder", (TreeListener,), recorded)
    return listener_class(), calls


@pytest.fixture(scope="module")
def flat_trees():
    """pymoca's flat trees of some library models (with cosim's patches applied)."""
    from pymoca import ast, tree

    pymoca_patches.apply()
    library = load_library()
    return {name: tree.flatten(library.tree, ast.ComponentRef.from_string(name)) for name in MODELS}


@pytest.mark.parametrize("walker_name", ["TreeWalker", "GeneratorWalker"])
@pytest.mark.parametrize("model", MODELS, ids=lambda m: m.rsplit(".", 1)[-1])
def test_fast_walk_makes_the_same_calls_as_pymocas_walk(flat_trees, model, walker_name):
    from pymoca.backends.casadi.generator import GeneratorWalker
    from pymoca.tree import TreeWalker

    walker = {"TreeWalker": TreeWalker, "GeneratorWalker": GeneratorWalker}[walker_name]()
    assert getattr(TreeWalker.walk, "_cosim_fast", False), "the fast walk is not installed"
    fast_listener, fast_calls = _recording_listener()
    TreeWalker.walk(walker, fast_listener, flat_trees[model])
    slow_listener, slow_calls = _recording_listener()
    TreeWalker.walk.original(walker, slow_listener, flat_trees[model])
    assert len(fast_calls) > 50  # the walk went through the model
    assert fast_calls == slow_calls
    assert fast_listener.context == slow_listener.context


def test_a_walker_of_its_own_keeps_pymocas_walk(flat_trees):
    """A TreeWalker subclass with other rules (here: skip equations) is walked by pymoca's code."""
    from pymoca.tree import TreeWalker

    class NoEquations(TreeWalker):
        def skip_child(self, tree, child_name):
            return child_name == "equations" or super().skip_child(tree, child_name)

    listener, calls = _recording_listener()
    NoEquations().walk(listener, flat_trees["Bicycle.Control.PID"])
    reference, expected = _recording_listener()
    TreeWalker.walk.original(NoEquations(), reference, flat_trees["Bicycle.Control.PID"])
    assert calls == expected
    assert not any(kind == "Equation" for _, _, kind, _ in calls)


@pytest.mark.parametrize("model", MODELS, ids=lambda m: m.rsplit(".", 1)[-1])
def test_scopes_kept_for_a_flattening_give_the_same_flat_model(model, monkeypatch):
    library = load_library()
    kept = _fingerprint(flatten(library, model), library.entry(model))
    # without the context, each full scope lives for one symbol's modifications (the old way)
    monkeypatch.setattr(pymoca_patches, "scopes_kept", contextlib.nullcontext)
    per_symbol = _fingerprint(flatten(library, model), library.entry(model))
    assert kept == per_symbol


def test_a_changed_scope_has_another_signature(flat_trees):
    """What pymoca may change in a partial scope between two symbols changes its key."""
    from pymoca import ast
    from pymoca.tree.instance import InstanceClass, InstanceSymbol

    scope = InstanceClass(name="", symbols={}, classes={}, extends=[])
    before = pymoca_patches._scope_signature(scope)
    scope.symbols["x"] = InstanceSymbol(name="x")
    assert pymoca_patches._scope_signature(scope) != before
    with_symbol = pymoca_patches._scope_signature(scope)
    scope.classes["Data"] = InstanceClass(name="Data")
    assert pymoca_patches._scope_signature(scope) != with_symbol
    with_class = pymoca_patches._scope_signature(scope)
    scope.classes["Data"].instantiation_state += 1  # redeclared/completed in place
    assert pymoca_patches._scope_signature(scope) != with_class
    completed = pymoca_patches._scope_signature(scope)
    scope.modification_environment = ast.ClassModification()
    assert pymoca_patches._scope_signature(scope) != completed


# --- the order of a parallel build ---------------------------------------------------------------

def test_longest_first_from_the_recorded_seconds(log_folder):
    schedule.record({"A.small": 0.1, "A.big": 4.0, "A.middle": 1.0})
    assert schedule.longest_first(["A.small", "A.new", "A.middle", "A.big", "A.other"]) == \
        ["A.new", "A.other", "A.big", "A.middle", "A.small"]  # unknown ones first, in the given order
    schedule.record({"A.small": 9.0})  # updated, the others kept
    assert schedule.longest_first(["A.small", "A.big", "A.middle"]) == ["A.small", "A.big", "A.middle"]


@pytest.mark.parametrize("content, order", [
    ("not json", ["A.small", "A.big"]),
    ("[1, 2]", ["A.small", "A.big"]),
    ('{"A.big": "slow", "A.small": 0.1}', ["A.big", "A.small"]),  # the bad entry alone is ignored
    ("", ["A.small", "A.big"]),
], ids=["garbage", "a-list", "a-bad-value", "empty"])
def test_an_unusable_log_only_means_the_given_order(content, order, log_folder):
    path = schedule.log_file()
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(content)
    assert schedule.longest_first(["A.small", "A.big"]) == order
    schedule.record({"A.big": 2.0})  # a bad log is replaced, not an error
    assert json.loads(path.read_text())["A.big"] == 2.0
    assert [p.name for p in path.parent.iterdir() if p.name != schedule.LOG_NAME] == []  # no temporary file left


def test_the_log_keeps_the_newest_entries(monkeypatch, log_folder):
    monkeypatch.setattr(schedule, "MAX_ENTRIES", 3)
    for k in range(5):
        schedule.record({f"M{k}": float(k)})
    assert list(schedule.recorded_seconds()) == ["M2", "M3", "M4"]


@pytest.fixture
def log_folder(tmp_path, monkeypatch):
    """A cache folder of the test's own (the build-time log lives there)."""
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    return tmp_path / "cache" / "cosim"


def test_a_parallel_build_starts_the_longest_first_and_answers_in_the_given_order(tmp_path, log_folder,
                                                                                   monkeypatch):
    from cosim.compiler import build as build_module

    started = []
    run_parallel = build_module._run_parallel

    def recording(tasks, jobs):
        started.extend(task[0] for task in tasks)
        return run_parallel(tasks, jobs)

    monkeypatch.setattr(build_module, "_run_parallel", recording)
    schedule.record({"Bicycle.Control.PD": 0.01, "Bicycle.Control.PID": 50.0})
    names = ["Bicycle.Control.PD", "Bicycle.Control.Proportional", "Bicycle.Control.PID"]
    results = build_module.build(names, tmp_path / "fmus", jobs=2)
    assert started == ["Bicycle.Control.Proportional", "Bicycle.Control.PID", "Bicycle.Control.PD"]
    assert [r.model for r in results] == names
    seconds = schedule.recorded_seconds()
    assert all(0 < seconds[name] < 50.0 for name in names)  # this build's times replaced the old ones
    again = build_module.build(names, tmp_path / "fmus", jobs=2)  # up to date: nothing to learn from
    assert not any(r.rebuilt for r in again) and schedule.recorded_seconds() == seconds
