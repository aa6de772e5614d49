"""``python -m cosim.matrix SPEC [options]``: the ``cosim matrix`` command on its own (one error
handling for both: the top command line runs it)."""
import sys

from cosim.cli import main

sys.exit(main(["matrix", *sys.argv[1:]]))
