within Bicycle.Records;
// Generated from cosim/analytic/parameters.py (SECOND_ORDER_UNITS) by python -m cosim.analytic.records: do not edit.
partial package PartialSecondOrder "Parameter set of the simple second-order bicycle models of Astrom, Klein and Lennartsson (2005)"
  constant Real m(final quantity = "Mass", final unit = "kg") "Total mass m of bicycle and rider";
  constant Real a(final quantity = "Length", final unit = "m") "Horizontal distance a from the rear contact point to the centre of mass";
  constant Real h(final quantity = "Length", final unit = "m") "Height h of the centre of mass above the ground";
  constant Real b(final quantity = "Length", final unit = "m") "Wheel base b";
  constant Real c(final quantity = "Length", final unit = "m") "Trail c";
  constant Real lambda(final quantity = "Angle", final unit = "rad") "Head angle lambda (pi/2: vertical steer axis)";
  constant Real J(final quantity = "MomentOfInertia", final unit = "kg.m2") "Moment of inertia J about the x axis";
  constant Real D(final quantity = "MomentOfInertia", final unit = "kg.m2") "Inertia product D = -Jxz";
  constant Real g(final quantity = "Acceleration", final unit = "m/s2") "Gravitational acceleration g";
  constant Real m_r(final quantity = "Mass", final unit = "kg") "Mass m_r of the rider's upper body (part of m)";
  constant Real J_r(final quantity = "MomentOfInertia", final unit = "kg.m2") "Moment of inertia J_r of the upper body with respect to the x axis";
  constant Real h_r(final quantity = "Length", final unit = "m") "Distance h_r from the centre of mass of the upper body to its lean axis";
  constant Real V(final quantity = "Velocity", final unit = "m/s") "Forward speed V (default operating point of the models)";
  constant Real R(final quantity = "Length", final unit = "m") "Lateral (rocking) radius R of the crowned rollers (default of the roller model)";
  constant Real k3(final quantity = "Time", final unit = "s") "Gain k3 of the gyroscopic derivative feedback from roll rate to steer angle (default)";
  annotation(Documentation(info = "<html><p>The lumped bicycle of the second-order models (ISO 8855 conventions, lambda is the head angle), the leaning rider of eqs (22)-(23) and the models' default operating values.</p></html>"));
end PartialSecondOrder;
