"""FMI 2.0 FMUs that misbehave on purpose, compiled from ``tests/data/hostile-fmu/hostile.c``.

Foreign FMUs must not take ``cosim`` down: these binaries segfault, call ``exit`` or ``abort``,
loop forever, kill their parent process, return NaN outputs or fail to instantiate, at a chosen
place (see the C source). gcc compiles one binary per case (about 0.1 s each).

Usage::

    from hostile_fmus import hostile_fmu
    fmu = hostile_fmu(tmp_path, "segfault", where="step")
"""
from __future__ import annotations

import shutil
import subprocess
import zipfile
from pathlib import Path

import fmpy

SOURCE = Path(__file__).resolve().parent / "data" / "hostile-fmu"
HEADERS = Path(fmpy.__file__).resolve().parent / "c-code"

#: The faults of hostile.c by name (the FAULT macro).
FAULTS = {"none": 0, "segfault": 1, "exit": 2, "abort": 3, "hang": 4, "kill-parent": 5, "nan": 6, "null-instance": 7}
#: Where a fault strikes (the WHERE macro).
PLACES = {"instantiate": 0, "step": 1, "initialization": 2}


def hostile_fmu(folder: Path | str, fault: str, where: str = "step", fault_time: float = 0.5) -> Path:
    """Compile the hostile FMU with ``fault`` striking ``where`` into ``folder/hostile-FAULT-WHERE.fmu``
    (``...-at-TIME.fmu`` for a ``fault_time`` other than 0.5 s).

    Parameters
    ----------
    folder : path
        Where the FMU (and its build tree) go.
    fault : str
        One of :data:`FAULTS`.
    where : str
        One of :data:`PLACES`; ``"step"`` strikes in ``fmi2DoStep`` and ``fmi2GetDerivatives`` from
        ``fault_time`` [s] on.
    """
    folder = Path(folder)
    name = f"hostile-{fault}-{where}" + ("" if fault_time == 0.5 else f"-at-{fault_time:g}")
    tree = folder / name
    binaries = tree / "binaries" / "linux64"
    binaries.mkdir(parents=True, exist_ok=True)
    shutil.copy(SOURCE / "modelDescription.xml", tree / "modelDescription.xml")
    subprocess.run(["gcc", "-shared", "-fPIC", "-O0", "-w", f"-I{HEADERS}", f"-DFAULT={FAULTS[fault]}",
                    f"-DWHERE={PLACES[where]}", f"-DFAULT_TIME={fault_time!r}", "-o",
                    str(binaries / "hostile.so"), str(SOURCE / "hostile.c"), "-lm"], check=True,
                   capture_output=True, text=True)
    fmu = folder / f"{name}.fmu"
    with zipfile.ZipFile(fmu, "w") as archive:
        for path in sorted(tree.rglob("*")):
            if path.is_file():
                archive.write(path, path.relative_to(tree).as_posix())
    return fmu
