"""The one registry of Python blocks: the system factory, SSP export, prediction and docs read it.

A block is one class, a subclass of :class:`Block`, and declares everything about itself there:

* its **parameters**: the keyword arguments of ``__init__`` (name, default, type annotation);
* its **Python stepping**: the :class:`~cosim.cosimulation.component.Component` protocol;
* its **Modelica twin**: ``twin`` (the class name in the Modelica library, e.g.
  ``"Bicycle.Control.PD"``) and :meth:`Block.twin_parameters` (the twin's parameter values; by
  default the parameters the system states, unchanged);
* its **linear model**: :meth:`Block.linear`, a :class:`~cosim.statespace.StateSpace`
  ``y = C x + D u + r(t)`` with ``r`` the exogenous part (:meth:`Block.exogenous`: sources,
  references) that stability does not see (the class attribute ``interpolates`` marks a block
  that does not hold its inputs over a communication step);
* its **native form** (optional): :meth:`Block.native`, a :class:`Native` description with which
  the master's C stepping loop (:mod:`cosim.cosimulation.fastloop`) steps the block exactly as its
  Python methods do. The shared kinds (``Affine``, ``Linear``, ``TransportDelay`` in
  :mod:`cosim.cosimulation.blocks`) have one, so a block derived from them, like ``Proportional``
  below, has it too; a system with a block without one is stepped by the Python loop.

Defining the class registers it under its class name (``register=False`` for abstract bases)::

    class Proportional(Affine):
        '''T = -k phi (k in N.m/rad).'''
        inputs, outputs, twin = ["phi"], ["T"], "Bicycle.Control.Proportional"

        def __init__(self, name, k: float = 10.0):
            super().__init__(name)
            self.k = float(k)

        def gain(self):
            return np.array([[-self.k]])

A new block is this class plus the ``.mo`` file of its twin (and its line in ``package.order``).
Blocks in other modules (e.g. the ``imports`` of a matrix spec) register the same way.
"""
from __future__ import annotations

import inspect
import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from cosim.errors import ParameterError
from cosim.cosimulation.component import Component
from cosim.statespace import StateSpace

#: Registered blocks by name (the ``python = "NAME"`` of a system file).
BLOCKS: dict[str, type[Block]] = {}
_SIGNATURES: dict[type, dict] = {}  # Block.parameters by class


@dataclass(frozen=True)
class Window:
    """A piecewise-constant signal: ``on`` while ``lo <= t + shift < hi``, else ``off`` (t, lo, hi,
    shift in s; ``on``, ``off`` one value per output).

    The exogenous part of the sources and references (:meth:`Block.exogenous`); written as data so
    that the C stepping loop evaluates the same comparisons on the same numbers (``shift`` is the
    round-off margin a jump on a communication point is reached with)."""

    lo: float
    hi: float
    shift: float
    on: tuple[float, ...]
    off: tuple[float, ...]

    def value(self, t: float) -> np.ndarray:
        """The signal at ``t`` [s], one value per output."""
        s = t + self.shift
        return np.array(self.on if self.lo <= s and s < self.hi else self.off)


@dataclass
class Native:
    """A block as the C stepping loop steps it (``fastloop.c`` reproduces the Python methods
    operation by operation, so both loops give bit-identical results).

    The arrays ``u``, ``y``, ``x`` and ``t`` are the block's own state, which the loop updates in
    place; after the loop ``done()`` copies back what the block keeps elsewhere (its time, a
    delay's sample history).

    Attributes
    ----------
    kind : str
        ``"affine"`` (``y = D u + r(t)``, :class:`~cosim.cosimulation.blocks.Affine`), ``"linear"``
        (``x(t + h) = Ad(h) x + Bd(h) u``, ``y = C x + D u``, :class:`~cosim.cosimulation.blocks.Linear`)
        or ``"delay"`` (the exact delay, :class:`~cosim.cosimulation.blocks.TransportDelay`).
    u, y : ndarray
        Inputs and outputs of the block.
    t : ndarray
        The block's time [s], one element.
    D : ndarray
        Outputs x inputs (affine, linear).
    window : Window or None
        The exogenous part ``r(t)`` (affine; None for 0).
    x, C : ndarray
        States and outputs x states (linear).
    Ad, Bd : ndarray
        Discrete matrices (linear), one ``(states x states)``, ``(states x inputs)`` pair per
        distinct step length, stacked on the first axis.
    which : ndarray
        For the block's j-th step, the index of its pair in ``Ad``, ``Bd`` (linear).
    tau : float
        The delay [s] (delay).
    ring_t, ring_v : ndarray
        Sample times [s] and values of the delay's input history, a ring buffer (delay).
    ring : ndarray
        First sample and number of samples in the ring (delay; int64).
    done : callable or None
        Called after the loop.
    """

    kind: str
    u: np.ndarray
    y: np.ndarray
    t: np.ndarray
    D: np.ndarray | None = None
    window: Window | None = None
    x: np.ndarray | None = None
    C: np.ndarray | None = None
    Ad: np.ndarray | None = None
    Bd: np.ndarray | None = None
    which: np.ndarray | None = None
    tau: float = 0.0
    ring_t: np.ndarray | None = None
    ring_v: np.ndarray | None = None
    ring: np.ndarray | None = None
    done: object = None


def _owner(cls: type, attribute: str) -> type | None:
    """The class in ``cls``'s MRO that defines ``attribute``."""
    return next((k for k in cls.__mro__ if attribute in vars(k)), None)


class Block(Component):
    """A registered Python block (see the module docstring).

    Class attributes
    ----------------
    inputs, outputs : list of str
        Names, the same as the twin's.
    twin : str or None
        Modelica class of the twin (None: the block cannot be exported).
    twin_same_parameters : bool
        True if the twin has the block's parameters, so the FMU of the twin is predicted by the
        block's linear model (False for LQR, whose parameters are design weights, and for the
        exact delay, whose twin approximates it).
    twin_approximation : str or None
        How the twin differs from the Python block, if it does (reported by SSP export).
    """

    twin: ClassVar[str | None] = None
    twin_same_parameters: ClassVar[bool] = True
    twin_approximation: ClassVar[str | None] = None

    def __init_subclass__(cls, register: bool = True, **kwargs):
        super().__init_subclass__(**kwargs)
        if not register:
            return
        old = BLOCKS.get(cls.__name__)
        if old is not None and (old.__module__, old.__qualname__) != (cls.__module__, cls.__qualname__):
            raise TypeError(f"Python block '{cls.__name__}' is defined twice: in {old.__module__} "
                            f"and {cls.__module__}")
        BLOCKS[cls.__name__] = cls  # a re-imported module replaces its own classes

    def __init__(self, name: str):
        super().__init__(name)
        self.given: dict = {}  # the parameters the system stated (set by create)
        self._t = 0.0

    # ------------------------------------------------------------------ declaration

    @classmethod
    def parameters(cls) -> dict[str, inspect.Parameter]:
        """The block's parameters: the keyword arguments of ``__init__`` after ``name``."""
        found = _SIGNATURES.get(cls)
        if found is None:  # inspect.signature costs ~50 us: once per class, not per block created
            found = _SIGNATURES[cls] = {k: p for k, p in inspect.signature(cls).parameters.items() if k != "name"}
        return dict(found)

    @classmethod
    def defaults(cls) -> dict:
        """Default value of every parameter."""
        return {k: p.default for k, p in cls.parameters().items() if p.default is not inspect.Parameter.empty}

    @classmethod
    def summary(cls) -> str:
        """The first paragraph of the class docstring, on one line."""
        return " ".join((inspect.getdoc(cls) or cls.__name__).split("\n\n")[0].split())

    @classmethod
    def create(cls, name: str, parameters: dict) -> Block:
        """The block with the system's parameter values, checked against ``__init__``'s signature.

        Raises
        ------
        ParameterError
            For an unknown parameter, a value of the wrong type, or one the block refuses.
        """
        accepted = cls.parameters()
        unknown = set(parameters) - set(accepted)
        if unknown:
            raise ParameterError(f"unknown parameter(s) {', '.join(sorted(unknown))}; "
                                 f"accepted: {', '.join(sorted(accepted))}")
        values = {k: _argument(k, v, accepted[k].annotation) for k, v in parameters.items()}
        block = cls(name, **values)
        block.given = values
        return block

    # ------------------------------------------------------------------ twin and linear model

    def twin_parameters(self) -> dict:
        """Parameter values of the Modelica twin (default: those the system states; the twin's
        defaults are the block's, checked by tests/test_block_registry.py)."""
        return dict(self.given)

    #: True for a block that does not hold its inputs over a communication step (the exact
    #: transport delay reads the input history): the prediction models no hold lag for it, and
    #: its linear model is an approximation, not the block.
    interpolates: ClassVar[bool] = False

    def linear(self, settings: dict) -> StateSpace:
        """The linear model ``y = C x + D u`` (+ :meth:`exogenous`); ``settings`` of a matrix spec
        (``pade_order``) where the block needs them."""
        raise NotImplementedError(f"{type(self).__name__} declares no linear model")

    def exogenous(self, t: float) -> np.ndarray:
        """The output part no input drives, at time ``t`` [s] (sources, references; default 0)."""
        return np.zeros(len(self.outputs))

    # ------------------------------------------------------------------ native form

    #: The methods whose arithmetic :meth:`native` describes: a subclass that overrides one of
    #: them without defining its own ``native`` is stepped by the Python loop.
    native_methods: ClassVar[tuple[str, ...]] = ("set_inputs", "get_outputs", "step", "exogenous")

    def native(self, steps: np.ndarray) -> Native | None:
        """The block's form for the C stepping loop, or None (default) if it has none.

        Called once per run after initialization, with ``steps`` the lengths [s] of the steps the
        block will take, in order. It must not change the block: the master may still decide to
        step in Python.
        """
        return None

    def native_form(self, steps: np.ndarray) -> Native | None:
        """:meth:`native` if the class's stepping is the one that ``native`` describes, else None."""
        cls = type(self)
        owner = _owner(cls, "native")
        if owner is None or owner is Block:
            return None
        for name in self.native_methods:
            defined = _owner(cls, name)
            if defined is not None and not issubclass(owner, defined):
                return None  # overridden below the description: not what native() describes
        return self.native(steps)

    # ------------------------------------------------------------------ the protocol, shared

    def setup(self, start_time: float) -> None:
        self._t = float(start_time)


def _argument(key: str, value, annotation: str):
    """A system-file value for a block argument, checked against the argument's annotation."""
    kind = str(annotation).split("|")[0].strip()
    if kind == "float":
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise ParameterError(f"parameter '{key}': expected a number, got {value!r}")
        if not math.isfinite(value):
            raise ParameterError(f"parameter '{key}': must be finite, got {value!r}")
        return float(value)
    if kind == "int":
        if isinstance(value, bool) or not isinstance(value, (int, float)) or value != int(value):
            raise ParameterError(f"parameter '{key}': expected a whole number, got {value!r}")
        return int(value)
    if kind == "str" and not isinstance(value, str):
        raise ParameterError(f"parameter '{key}': expected a string, got {value!r}")
    return value


def _load() -> dict[str, type[Block]]:
    """The registry with the built-in blocks imported (they register when their module loads)."""
    # deferred: blocks and controllers import this module to register with it
    from cosim.cosimulation import blocks, controllers  # noqa: F401

    return BLOCKS


def registered() -> dict[str, type[Block]]:
    """Every registered block by name (built-in ones first)."""
    return dict(_load())


def lookup(block: str) -> type[Block]:
    """The class of a block by name.

    Raises
    ------
    ParameterError
        If no block has that name (the message lists the known ones).
    """
    found = _load().get(block)
    if found is None:
        raise ParameterError(f"unknown Python block '{block}' (available: {', '.join(BLOCKS)})")
    return found


def for_twin(model: str) -> type[Block] | None:
    """The block whose linear model describes the FMU of the Modelica class ``model`` (None if none)."""
    for cls in _load().values():
        if cls.twin == model and cls.twin_same_parameters:
            return cls
    return None


def markdown() -> str:
    """The blocks as one Markdown line each: name, twin, inputs -> outputs, summary (for the documentation)."""
    lines = []
    for name, cls in registered().items():
        arrow = f"{', '.join(cls.inputs) or '()'} -> {', '.join(cls.outputs)}"
        twin = f"`{cls.twin}`" + (f" ({cls.twin_approximation})" if cls.twin_approximation else "")
        lines.append(f"- `{name}` ({arrow}; twin {twin}): {cls.summary()}")
    return "\n".join(lines)
