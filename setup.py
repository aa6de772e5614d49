"""Only what pyproject.toml cannot say: the Modelica library (``modelica/`` of the source tree)
ships inside the package as ``cosim/modelica``, so a normal (non-editable) install finds it."""
from setuptools import find_packages, setup

setup(packages=find_packages(include=["cosim*"]) + ["cosim.modelica"],
      package_dir={"cosim.modelica": "modelica"})
