"""``python -m cosim.matrix SPEC [options]``: the ``cosim matrix`` command on its own."""
import sys

from cosim.matrix.cli import main

sys.exit(main())
