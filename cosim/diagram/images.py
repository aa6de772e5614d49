"""The diagrams that the documentation shows: the SVGs of the bicycles and the examples in the
library's ``Bicycle/Resources/Images`` (the UsersGuide refers to them as
``modelica://Bicycle/Resources/Images/...``, the README and ``docs/diagrams.md`` by path).

They are drawn from the library's annotations, so they are written, not edited:
``python -m cosim.diagram.images`` writes them anew; ``tests/test_diagram_images.py`` checks that the
committed ones are what the library draws today.
"""
from __future__ import annotations

import sys
from pathlib import Path

from cosim.compiler.library import DEFAULT_LIBRARY, Library
from cosim.diagram.svg import draw

#: The models whose diagrams the documentation shows, besides every example.
BICYCLES = ("Bicycle.Bicycles.Whipple", "Bicycle.Bicycles.WhippleRider", "Bicycle.Bicycles.WhippleRiderTwist",
            "Bicycle.Bicycles.WhippleLinear")


def image_folder(root: Path = DEFAULT_LIBRARY) -> Path:
    """``Bicycle/Resources/Images`` of the library folder ``root``."""
    return root / "Bicycle" / "Resources" / "Images"


def models(library: Library) -> list[str]:
    """The bicycles of :data:`BICYCLES` and every example of the library."""
    return list(BICYCLES) + [e.name for e in library.models() if e.name.startswith("Bicycle.Examples.")]


def file_name(model: str) -> str:
    """``Whipple.svg`` for ``Bicycle.Bicycles.Whipple`` (the model's short name: unique among them)."""
    return model.rsplit(".", 1)[-1] + ".svg"


def drawings(root: Path = DEFAULT_LIBRARY) -> dict[str, str]:
    """File name -> SVG text of every documented diagram, drawn from the library in ``root``."""
    library = Library(root)
    return {file_name(m): draw(m, library=library).svg for m in models(library)}


def main(argv=None) -> int:
    folder = image_folder()
    folder.mkdir(parents=True, exist_ok=True)
    for name, svg in drawings().items():
        (folder / name).write_text(svg, encoding="utf-8")
        print(folder / name)
    return 0


if __name__ == "__main__":
    sys.exit(main())
