within Bicycle.Control;
block LeanSteer "Rider using steer torque and upper-body lean: T = -k*phi - kd*phi_dot, theta = -k_lean*phi"
  parameter Real k(unit = "N.m/rad") = 10 "Steer torque per radian of roll";
  parameter Real kd(unit = "N.m.s/rad") = 1 "Steer torque per rad/s of roll rate";
  parameter Real k_lean(unit = "1") = 0.5 "Upper-body lean per radian of roll";
  Bicycle.Interfaces.RealInput phi(final quantity = "Angle", final unit = "rad", displayUnit = "deg") "Roll angle";
  Bicycle.Interfaces.RealInput phi_dot(final quantity = "AngularVelocity", final unit = "rad/s") "Roll rate";
  Bicycle.Interfaces.RealOutput T(final quantity = "Torque", final unit = "N.m") "Steer torque";
  Bicycle.Interfaces.RealOutput theta(final quantity = "Angle", final unit = "rad", displayUnit = "deg") "Upper-body lean angle relative to the frame";
equation
  T = -k*phi - kd*phi_dot;
  theta = -k_lean*phi;
  annotation(__Cosim(export = true), Documentation(info = "<html>
<p>Inputs (<a href=\"modelica://Bicycle.Interfaces.RealInput\">RealInput</a>): <code>phi</code>
(rad), <code>phi_dot</code> (rad/s); outputs (<a
href=\"modelica://Bicycle.Interfaces.RealOutput\">RealOutput</a>): <code>T</code> (steer torque,
N.m), <code>theta</code> (upper-body lean, rad). The FMU has the same input and output names.
Modelica twin of the Python block <code>LeanSteer</code>
(<code>cosim.cosimulation.controllers</code>).</p>
</html>"));
end LeanSteer;
