"""``python -m cosim.matrix SPEC [options]``: the ``cosim matrix`` command on its own."""
import sys

from .cli import main

sys.exit(main())
