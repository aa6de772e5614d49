"""The interface of a coupling algorithm of the master, and the registry that finds them by name.

A coupling algorithm is one class: a subclass of :class:`CouplingAlgorithm` with its ``name`` (the
value of ``algorithm`` in a system file's ``[system]`` table) and what the parts of the package
that depend on it read from it:

* the master (:mod:`cosim.cosimulation.master`): whether components step one after another
  (``sequential``), the integer by which its C loop knows the algorithm (``fast_code``), or that
  all components are integrated together as one ODE instead (``one_ode``);
* the analytic prediction of a case (:mod:`cosim.matrix.predict`): the lags the algorithm adds to
  a connection (:meth:`CouplingAlgorithm.output_lag`, :meth:`CouplingAlgorithm.hold_lag`);
* the SSP export (:mod:`cosim.cosimulation.ssp`): the OSP and OMSimulator annotations that make
  other engines run the same algorithm (``osp_algorithm``, ``omsimulator_master``).

Decorating the class with :func:`register` makes it known everywhere a system is read, checked,
run, predicted or exported.
"""
from __future__ import annotations

from typing import ClassVar

from cosim.errors import CosimError


class UnknownAlgorithm(CosimError, KeyError):
    """No coupling algorithm of that name is registered; the message lists the registered ones."""

    def __str__(self) -> str:  # KeyError would quote the message
        return str(self.args[0]) if self.args else ""


class CouplingAlgorithm:
    """A coupling algorithm of the master; subclasses set the class attributes and register with
    :func:`register`."""

    #: The value of ``algorithm`` in a system file that selects it (lower case).
    name: ClassVar[str] = ""
    #: Components step one after another in an order along their direct feedthrough, each after
    #: its inputs took the outputs the components before it computed in the same step; False:
    #: every component steps from the outputs of the previous communication point.
    sequential: ClassVar[bool] = False
    #: The integer by which the master's C loop (``cosim_fast_run`` in fastloop.c) knows the
    #: algorithm: 0 every component from the previous communication point, 1 sequential; None:
    #: the C loop does not step it (the Python loop does).
    fast_code: ClassVar[int | None] = None
    #: All components are integrated together as one ODE (:mod:`cosim.cosimulation.model_exchange`)
    #: instead of being stepped with their inputs held.
    one_ode: ClassVar[bool] = False
    #: The OSP annotation element (``osp:<name>`` under ``osp:Algorithm``) that describes the
    #: algorithm to libcosim and Ecos; None: an SSP cannot describe it (no export).
    osp_algorithm: ClassVar[str | None] = None
    #: OMSimulator's name of the master that runs it (``description`` of ``oms:FixedStepMaster``);
    #: None: OMSimulator has none.
    omsimulator_master: ClassVar[str | None] = None

    def output_lag(self, step: float) -> float | None:
        """Lag [s] the algorithm adds to the output of a component without states (a static
        gain) stepped every ``step`` [s], as its connected input sees it; None: the analytic
        prediction does not model the algorithm."""
        return None

    def hold_lag(self, step: float) -> float | None:
        """Lag [s] of the inputs of a component with states stepped every ``step`` [s] (the
        inputs held over the step); None: the analytic prediction does not model the algorithm."""
        return None

    @property
    def in_c_loop(self) -> bool:
        """True if the master's C loop can step the algorithm (it has a ``fast_code``)."""
        return self.fast_code is not None

    @property
    def predicted(self) -> bool:
        """True if the analytic prediction (:mod:`cosim.matrix.predict`) models the algorithm."""
        return self.output_lag(1.0) is not None and self.hold_lag(1.0) is not None

    @property
    def exports_to_ssp(self) -> bool:
        """True if an SSP archive can describe the algorithm to other engines."""
        return self.osp_algorithm is not None and self.omsimulator_master is not None

    def __repr__(self) -> str:
        return f"<coupling algorithm {self.name!r}>"


_REGISTERED: dict[str, CouplingAlgorithm] = {}


def register(cls: type[CouplingAlgorithm]) -> type[CouplingAlgorithm]:
    """Class decorator: make the algorithm ``cls`` known by its ``name`` (after those registered
    before it).

    Raises
    ------
    ValueError
        If the name is empty, not lower case, or taken by another class.
    """
    name = cls.name
    if not name or name != name.lower():
        raise ValueError(f"{cls.__qualname__}: a coupling algorithm needs a lower-case name, got {name!r}")
    if name in _REGISTERED and type(_REGISTERED[name]) is not cls:
        raise ValueError(f"{cls.__qualname__}: the coupling algorithm name {name!r} is taken by "
                         f"{type(_REGISTERED[name]).__qualname__}")
    _REGISTERED[name] = cls()
    return cls


def unregister(name: str) -> None:
    """Forget the algorithm ``name`` (nothing if it is not registered)."""
    _REGISTERED.pop(name, None)


def names() -> tuple[str, ...]:
    """The names of the registered algorithms, in the order they were registered."""
    return tuple(_REGISTERED)


def algorithms(**where) -> list[CouplingAlgorithm]:
    """The registered algorithms, in the order they were registered; with keywords only those
    whose attributes have the given values (``algorithms(one_ode=False)``)."""
    return [a for a in _REGISTERED.values() if all(getattr(a, k) == v for k, v in where.items())]


def algorithm(name: str) -> CouplingAlgorithm:
    """The registered algorithm called ``name`` (any case).

    Raises
    ------
    UnknownAlgorithm
        If none is, naming the registered ones.
    """
    found = _REGISTERED.get(str(name).lower())
    if found is None:
        raise UnknownAlgorithm(f"unknown coupling algorithm '{name}' (known: {', '.join(_REGISTERED)})")
    return found
