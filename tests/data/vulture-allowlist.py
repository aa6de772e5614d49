# Names that vulture (tests/test_dead_code.py) sees no use of because they are used from outside
# Python's name lookup. Read by vulture, never run. One entry per line, with the reason.
# ruff: noqa
__getattr__  # cosim/__init__.py: the module hook (PEP 562) that imports the public API lazily
__dir__  # cosim/__init__.py: the module hook (PEP 562) that lists the lazily imported API
_.expected_poles  # analytic/compare.py: a field of PairComparison, read by asdict in to_dict
_.expected_zeros  # analytic/compare.py: a field of PairComparison, read by asdict in to_dict
_.expected_gain  # analytic/compare.py: a field of PairComparison, read by asdict in to_dict
_.log_message  # app/server.py: overrides http.server's request log (silenced)
_._cosim_added_keys  # compiler/pymoca_patches.py: called by the patched pymoca source text it execs
_._cosim_leaf_dimensions  # compiler/pymoca_patches.py: called by the patched pymoca source text it execs
PadeDelay  # cosimulation/blocks.py: a Python block, found by its class name from system files
PD  # cosimulation/controllers.py: a Python block, found by its class name from system files
PID  # cosimulation/controllers.py: a Python block, found by its class name from system files
SteerAngleFeedback  # cosimulation/controllers.py: a Python block, found by its class name from system files
LQR  # cosimulation/controllers.py: a Python block, found by its class name from system files
LaneChange  # cosimulation/controllers.py: a Python block, found by its class name from system files
LeanSteer  # cosimulation/controllers.py: a Python block, found by its class name from system files
_.event_handling_needed  # cosimulation/component.py: a ctypes Structure field that fastloop.c reads
_.has_window  # cosimulation/fastloop.py: a ctypes Structure field that fastloop.c reads
_.x_next  # cosimulation/fastloop.py: a ctypes Structure field that fastloop.c reads
mtime_ns  # diagram/annotations.py: part of the lru_cache key, so that an edited file is parsed again
_.border_pattern  # diagram/graphics.py: an attribute of the Modelica Rectangle record (MLS 18.6.4)
_.initial_scale  # diagram/graphics.py: an attribute of the Modelica CoordinateSystem record (MLS 18.5)
instance_name  # fmu/access.py: a parameter of the FMI 2 logger callback's C signature
instance_environment  # fmu/access.py: a parameter of the FMI 3 logger callback's C signature
_.allocateMemory  # fmu/access.py: an fmi2CallbackFunctions field that the FMU calls through ctypes
_.freeMemory  # fmu/access.py: an fmi2CallbackFunctions field that the FMU calls through ctypes
unraisable  # fmu/simulate.py: the parameter of sys.unraisablehook's signature
_._print_Pow  # nonlinear/modelica.py: sympy's printer dispatches on the method name
_._print_Rational  # nonlinear/modelica.py: sympy's printer dispatches on the method name
_._print_Float  # nonlinear/modelica.py: sympy's printer dispatches on the method name
_._print_Integer  # nonlinear/modelica.py: sympy's printer dispatches on the method name
_._print_Symbol  # nonlinear/modelica.py: sympy's printer dispatches on the method name
rational  # nonlinear/modelica.py: a parameter of sympy's _print_Pow signature
_.terminal  # nonlinear/periodic.py: scipy's solve_ivp reads an event function's attribute
_.lean_only  # nonlinear/rider.py: a field of the PathZeros result, beside steer_only and both
