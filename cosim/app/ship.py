"""``python -m cosim.app.ship [--check] [-o DIR]``: make the WebAssembly modules and diagrams the
package ships for the app (``cosim/app/modules/``, :mod:`cosim.app.shipped`).

The FMUs of :data:`cosim.app.export.MODULES` are built into the FMU folder (``$COSIM_FMU_DIR``,
else ``./fmus``) and compiled to WebAssembly beside them by `cosim build --wasm` machinery, both
incremental; their NAME.wasm and NAME.json are copied unchanged. The diagrams are drawn from the
parsed library. Run it after changing the library, the compiler, the FMU runtime, the
WebAssembly build or the diagram layer (tests/test_app_shipped.py fails until the files are
made again); ``--check`` writes nothing and exits 1 if a file differs. Needs the ``wasm`` extra
(Zig).
"""
from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from cosim.errors import CosimError
from cosim.outputs import atomic_output, check_output_folder
from cosim.app.bicycles import page_data
from cosim.app.diagrams import page_diagrams
from cosim.app.export import MODEL, _fmu_folder, build_modules, diagram_models
from cosim.app.shipped import DIAGRAMS, FORMAT, MANIFEST, SHIPPED, module_name, sources_key
from cosim.compiler.library import tool_versions
from cosim.wasm.build import zig_command, zig_version


def made(fmu_folder: Path | None = None) -> dict[str, bytes]:
    """The shipped files as the sources make them now: file name -> content.

    Parameters
    ----------
    fmu_folder : path, optional
        Where the FMUs and their modules are built (default ``$COSIM_FMU_DIR``, else ``./fmus``).

    Raises
    ------
    BuildError, MissingExtraError
        If an FMU or its WebAssembly module cannot be built (e.g. no ``ziglang`` wheel).
    """
    zig_command()  # no ziglang: one message before any work
    files, descriptions, names = {}, {}, {}
    for model, wasm in build_modules(fmu_folder or _fmu_folder()).items():
        name = module_name(model)
        files[f"{name}.wasm"] = wasm.wasm.read_bytes()
        files[f"{name}.json"] = wasm.description.read_bytes()
        descriptions[model] = json.loads(files[f"{name}.json"])
        names[model] = name
    models = diagram_models(page_data(descriptions[MODEL], descriptions)["bicycles"])
    files[DIAGRAMS] = _json(page_diagrams(models))
    files[MANIFEST] = _json({"format": FORMAT, "key": sources_key(), "modules": names, "diagrams": models,
                             "zig": zig_version(), "tools": tool_versions()}, indent=1)
    return files


def _json(value, indent=None) -> bytes:
    return (json.dumps(value, indent=indent, separators=(",", ": ") if indent else (",", ":")) + "\n").encode()


def differences(files: dict[str, bytes], folder: Path = SHIPPED) -> list[str]:
    """The names of the files that differ between ``files`` and ``folder`` (missing, other
    bytes, or in ``folder`` only), sorted."""
    present = {p.name for p in folder.glob("*") if p.is_file()} if folder.is_dir() else set()
    changed = {name for name, data in files.items() if name not in present or (folder / name).read_bytes() != data}
    return sorted(changed | (present - set(files)))


def write(files: dict[str, bytes], folder: Path = SHIPPED) -> None:
    """Write ``files`` into ``folder`` (each atomically) and remove the other files there.

    Raises
    ------
    OutputError
        If ``folder`` is not a folder or cannot be written.
    """
    check_output_folder(folder, "shipped app folder")
    for name, data in files.items():
        with atomic_output(folder / name, "shipped app file") as partial:
            partial.write_bytes(data)
    for path in folder.glob("*"):
        if path.is_file() and path.name not in files:
            path.unlink()


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m cosim.app.ship", description=__doc__.split("\n\n")[0])
    parser.add_argument("-o", "--output", type=Path, default=SHIPPED, help=f"default: {SHIPPED}")
    parser.add_argument("--check", action="store_true", help="do not write; exit 1 if a file differs")
    args = parser.parse_args(argv)
    try:
        if not args.check:  # an unusable folder: its message before any build
            check_output_folder(args.output, "shipped app folder")
        files = made()
        changed = differences(files, args.output)
        if not args.check:
            write(files, args.output)
    except CosimError as exc:
        print(f"{parser.prog}: error: {exc}", file=sys.stderr)
        return 2
    verb = "differ" if args.check else "written"
    print(f"{args.output}: {', '.join(changed) + ' ' + verb if changed else 'up to date'}")
    return 1 if args.check and changed else 0


if __name__ == "__main__":
    sys.exit(main())
