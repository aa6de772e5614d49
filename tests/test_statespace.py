"""The one state-space type (:class:`cosim.statespace.StateSpace`): its constructor's shapes and
names, its python-control form, and that no other class of the package declares A, B, C, D."""
from __future__ import annotations

import ast
from pathlib import Path

import numpy as np
import pytest

from cosim.statespace import StateSpace

ROOT = Path(__file__).resolve().parents[1]

CASES = {
    # name: (A, B, C, D, inputs, outputs, states, n)
    "static gain": ([], np.zeros((0, 1)), np.zeros((2, 0)), [[2.0], [-2.0]], ["u"], ["y1", "y2"], None, 0),
    "scalar lag": ([[-3.0]], [[1.0]], [[3.0]], [[0.0]], ["u"], ["y"], None, 1),
    "named states": ([[0, 1], [-4, -0.5]], [0, 1], [1, 0], 0, ["T"], ["phi"], ["phi", "phi_dot"], 2),
}


@pytest.mark.parametrize("A, B, C, D, inputs, outputs, states, n", CASES.values(), ids=CASES.keys())
def test_of_shapes_and_names(A, B, C, D, inputs, outputs, states, n):
    """Array-likes reshaped to the sizes the names give, as floats; unnamed states x[1], x[2], ..."""
    s = StateSpace.of(A, B, C, D, inputs, outputs, states)
    assert s.n == n
    assert (s.A.shape, s.B.shape, s.C.shape, s.D.shape) == ((n, n), (n, len(inputs)), (len(outputs), n),
                                                            (len(outputs), len(inputs)))
    assert all(m.dtype == float for m in (s.A, s.B, s.C, s.D))
    assert s.states == (list(states) if states else [f"x[{k + 1}]" for k in range(n)])
    assert (s.inputs, s.outputs) == (inputs, outputs)
    assert s.eigenvalues.shape == (n,)


@pytest.mark.parametrize("A, B, C, D, inputs, outputs, states, n", CASES.values(), ids=CASES.keys())
def test_to_control_keeps_matrices_and_names(A, B, C, D, inputs, outputs, states, n):
    """python-control's StateSpace holds the same numbers (bit for bit) and names."""
    s = StateSpace.of(A, B, C, D, inputs, outputs, states)
    sys = s.to_control("plant")
    for name in "ABCD":
        np.testing.assert_array_equal(getattr(sys, name), getattr(s, name), err_msg=name)
    assert (list(sys.state_labels), list(sys.input_labels), list(sys.output_labels)) == (s.states, s.inputs,
                                                                                         s.outputs)
    assert sys.name == "plant"


def test_no_other_class_declares_state_space_matrices():
    """Containers hold a StateSpace instead of fields A, B, C, D of their own."""
    found = []
    for path in sorted((ROOT / "cosim").rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text(), str(path))):
            if isinstance(node, ast.ClassDef):
                fields = {item.target.id for item in node.body
                          if isinstance(item, ast.AnnAssign) and isinstance(item.target, ast.Name)}
                if {"A", "B"} <= fields:
                    found.append(f"{path.relative_to(ROOT)}: {node.name}")
    assert found == ["cosim/statespace.py: StateSpace"], found
