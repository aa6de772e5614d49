within Bicycle.Records;
// Generated from cosim/params/second-order/astrom2005.toml by python -m cosim.analytic.records: do not edit.
package Astrom2005SecondOrder "Bicycle of Astrom, Klein and Lennartsson (2005) for the second-order models (generated from cosim/params/second-order/astrom2005.toml)"
  constant Real m(final quantity = "Mass", final unit = "kg") = 92.0 "Total mass m of bicycle and rider";
  constant Real a(final quantity = "Length", final unit = "m") = 0.5 "Horizontal distance a from the rear contact point to the centre of mass";
  constant Real h(final quantity = "Length", final unit = "m") = 1.0 "Height h of the centre of mass above the ground";
  constant Real b(final quantity = "Length", final unit = "m") = 1.0 "Wheel base b";
  constant Real c(final quantity = "Length", final unit = "m") = 0.08 "Trail c";
  constant Real lambda(final quantity = "Angle", final unit = "rad") = 1.2217304763960306 "Head angle lambda (pi/2: vertical steer axis)";
  constant Real J(final quantity = "MomentOfInertia", final unit = "kg.m2") = 96.7 "Moment of inertia J about the x axis";
  constant Real D(final quantity = "MomentOfInertia", final unit = "kg.m2") = 46.3 "Inertia product D = -Jxz";
  constant Real g(final quantity = "Acceleration", final unit = "m/s2") = 9.81 "Gravitational acceleration g";
  constant Real m_r(final quantity = "Mass", final unit = "kg") = 40.0 "Mass m_r of the rider's upper body (part of m)";
  constant Real J_r(final quantity = "MomentOfInertia", final unit = "kg.m2") = 16.0 "Moment of inertia J_r of the upper body with respect to the x axis";
  constant Real h_r(final quantity = "Length", final unit = "m") = 0.35 "Distance h_r from the centre of mass of the upper body to its lean axis";
  constant Real V(final quantity = "Velocity", final unit = "m/s") = 5.0 "Forward speed V (default operating point of the models)";
  constant Real R(final quantity = "Length", final unit = "m") = 0.3 "Lateral (rocking) radius R of the crowned rollers (default of the roller model)";
  constant Real k3(final quantity = "Time", final unit = "s") = 0.05 "Gain k3 of the gyroscopic derivative feedback from roll rate to steer angle (default)";
  annotation(Documentation(info = "<html><p>Data set generated from <code>cosim/params/second-order/astrom2005.toml</code> (the one source of these values) by <code>python -m cosim.analytic.records</code>. A model takes it as <code>replaceable package Data = Bicycle.Records.Astrom2005SecondOrder constrainedby Bicycle.Records.PartialSecondOrder</code>.</p></html>"));
end Astrom2005SecondOrder;
