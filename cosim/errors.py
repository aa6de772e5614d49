"""Exceptions of the cosim package.

Every error a user can cause derives from a built-in type (as in python-control) and from
:class:`CosimError`, which the command line turns into one message and a non-zero exit.
"""


class CosimError(Exception):
    """Base of all errors that are reported to the user without a traceback."""


class ModelicaError(CosimError, ValueError):
    """The Modelica source is invalid; the message names file, line and column."""


class UnknownModelError(CosimError, LookupError):
    """A model name that is not in the library; the message lists the known models."""

    def __str__(self):  # LookupError would quote the message
        return str(self.args[0]) if self.args else ""


class ModelStructureError(CosimError, ValueError):
    """The flattened model cannot be turned into an explicit ODE (unbalanced, index > 1, ...)."""


class ParameterError(CosimError, ValueError):
    """A parameter value is unknown or not acceptable; the message names the parameter."""


class BuildError(CosimError, RuntimeError):
    """Compiling or packaging an FMU failed."""


class SimulationError(CosimError, RuntimeError):
    """Running an FMU failed."""


class OutputError(CosimError, OSError):
    """An output file or folder cannot be written; the message names the path."""

    def __str__(self):  # OSError would format (errno, strerror)
        return str(self.args[0]) if self.args else ""


class ResultNotWritten(OutputError):
    """Computed results could not (all) be written: the disk is full, a quota exceeded, the file
    system read-only, ... The message names the path, the reason and what was kept or lost; the
    command line exits with status 4 (an incomplete result)."""


class FMUError(CosimError, ValueError):
    """A file given as an FMU is not a readable FMU (not a zip, no or broken modelDescription.xml,
    unsafe member names, unsupported FMI version); the message names the file and the problem."""


class InputDataError(CosimError, ValueError):
    """Input data (a CSV, TOML or parameter file) is malformed; the message names file, row and column."""


class MissingExtraError(CosimError, ImportError):
    """A feature needs a package of an optional extra that is not installed; the message names
    the feature, the package and the ``pip install`` command of the extra."""

    def __init__(self, feature: str, package: str, extra: str):
        super().__init__(f"{feature} needs {package}, from the optional extra '{extra}': "
                         f"pip install 'bicycle-cosim[{extra}]'")
        self.feature, self.package, self.extra = feature, package, extra

    def __str__(self):  # ImportError would add nothing; keep the one line
        return str(self.args[0]) if self.args else ""
