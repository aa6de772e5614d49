within Bicycle.Records;
// Generated from cosim/analytic/parameters.py (UPPER_BODY_UNITS) by python -m cosim.analytic.records: do not edit.
partial package PartialWhippleRider "Parameter set of the Whipple bicycle with the rider's upper body U on a hip hinge"
  extends Bicycle.Records.PartialWhipple;
  constant Real mU(final quantity = "Mass", final unit = "kg") "Upper body mass mU";
  constant Real xU(final quantity = "Length", final unit = "m") "Hinge (hip) axis and upper body centre of mass: x coordinate xU (forward)";
  constant Real hU(final quantity = "Length", final unit = "m") "Height hU of the hinge (hip) axis above the ground (upright bicycle)";
  constant Real lU(final quantity = "Length", final unit = "m") "Height lU of the upper body centre of mass above the hinge axis";
  constant Real IUxx(final quantity = "MomentOfInertia", final unit = "kg.m2") "Upper body inertia-tensor element IUxx about its centre of mass";
  constant Real IUxz(final quantity = "MomentOfInertia", final unit = "kg.m2") "Upper body inertia-tensor element IUxz about its centre of mass";
  constant Real IUyy(final quantity = "MomentOfInertia", final unit = "kg.m2") "Upper body inertia-tensor element IUyy about its centre of mass";
  constant Real IUzz(final quantity = "MomentOfInertia", final unit = "kg.m2") "Upper body inertia-tensor element IUzz about its centre of mass";
  constant Real kU(final quantity = "RotationalSpringConstant", final unit = "N.m/rad") "Passive stiffness kU of the hip hinge (lean torque per lean angle)";
  constant Real cU(final quantity = "RotationalDampingConstant", final unit = "N.m.s/rad") "Passive damping cU of the hip hinge (lean torque per lean rate)";
  annotation(Documentation(info = "<html><p>The Meijaard symbols (rear frame B <em>without</em> the upper body) and the upper body U: hinge axis parallel to x at x = xU, height hU; centre of mass lU above the hinge; inertia about its centre of mass in axes parallel to the rear frame's; passive hinge stiffness kU and damping cU.</p></html>"));
end PartialWhippleRider;
