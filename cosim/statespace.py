"""The one state-space type of the package: ``x' = A x + B u``, ``y = C x + D u`` with named
states, inputs and outputs.

FMU linearizations (:mod:`cosim.fmu.linearize`), the bicycle's steady-motion reduction and speed
sweeps (:mod:`cosim.bicycle.linearize`), the linear models the Python blocks declare
(:meth:`cosim.cosimulation.registry.Block.linear`) and the components of the analytic prediction
(:mod:`cosim.matrix.predict`) are, or hold, a :class:`StateSpace`. :meth:`StateSpace.to_control`
gives python-control's ``StateSpace`` with the same names.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass
class StateSpace:
    """``x' = A x + B u``, ``y = C x + D u`` (continuous time; units those of the signals named).

    Attributes
    ----------
    A, B, C, D : ndarray
        States x states, states x inputs, outputs x states, outputs x inputs.
    states, inputs, outputs : list of str
        The names of the states, inputs and outputs, in the order of the matrices' rows and columns.
    """

    A: np.ndarray
    B: np.ndarray
    C: np.ndarray
    D: np.ndarray
    states: list[str]
    inputs: list[str]
    outputs: list[str]

    @classmethod
    def of(cls, A, B, C, D, inputs, outputs, states=None) -> StateSpace:
        """A system from array-likes reshaped to the sizes the names give (float; an empty ``A``
        is no states); ``states`` default ``x[1]``, ``x[2]``, ... (the states of a block are
        not named)."""
        n = np.size(A) and np.shape(np.atleast_2d(A))[0]
        A = np.asarray(A, float).reshape(n, n)
        B = np.asarray(B, float).reshape(n, len(inputs))
        C = np.asarray(C, float).reshape(len(outputs), n)
        D = np.asarray(D, float).reshape(len(outputs), len(inputs))
        names = list(states) if states is not None else [f"x[{k + 1}]" for k in range(n)]
        return cls(A, B, C, D, names, list(inputs), list(outputs))

    @property
    def n(self) -> int:
        """Number of states."""
        return self.A.shape[0]

    @property
    def eigenvalues(self) -> np.ndarray:
        """The eigenvalues [1/s] of ``A`` (LAPACK's order; none without states)."""
        return np.linalg.eigvals(self.A) if self.A.size else np.zeros(0, complex)

    def to_control(self, name: str | None = None):
        """python-control's ``StateSpace`` with the same matrices and names."""
        import control

        return control.ss(self.A, self.B, self.C, self.D, states=self.states, inputs=self.inputs,
                          outputs=self.outputs, name=name)
