within Bicycle.Control;
block LeanSteer "Rider using steer torque and upper-body lean: T = -k*phi - kd*phi_dot, theta = -k_lean*phi"
  extends Bicycle.Icons.Block;
  parameter Real k(unit = "N.m/rad") = 10 "Steer torque per radian of roll";
  parameter Real kd(unit = "N.m.s/rad") = 1 "Steer torque per rad/s of roll rate";
  parameter Real k_lean(unit = "1") = 0.5 "Upper-body lean per radian of roll";
  Bicycle.Interfaces.RealInput phi(final quantity = "Angle", final unit = "rad", displayUnit = "deg") "Roll angle"
    annotation(Placement(transformation(extent = {{-140, 20}, {-100, 60}})));
  Bicycle.Interfaces.RealInput phi_dot(final quantity = "AngularVelocity", final unit = "rad/s") "Roll rate"
    annotation(Placement(transformation(extent = {{-140, -60}, {-100, -20}})));
  Bicycle.Interfaces.RealOutput T(final quantity = "Torque", final unit = "N.m") "Steer torque"
    annotation(Placement(transformation(extent = {{100, 30}, {120, 50}})));
  Bicycle.Interfaces.RealOutput theta(final quantity = "Angle", final unit = "rad", displayUnit = "deg") "Upper-body lean angle relative to the frame"
    annotation(Placement(transformation(extent = {{100, -50}, {120, -30}})));
equation
  T = -k*phi - kd*phi_dot;
  theta = -k_lean*phi;
  annotation(
    Icon(graphics = {
      Text(extent = {{-60, 70}, {90, 10}}, textString = "T", textColor = {0, 0, 0}),
      Text(extent = {{-60, -10}, {90, -70}}, textString = "θ", textColor = {0, 0, 0}),
      Text(extent = {{-150, -150}, {150, -110}}, textString = "k=%k, k_lean=%k_lean", textColor = {0, 0, 0})}),
    __Cosim(export = true),
    Documentation(info = "<html>
<p>Inputs (<a href=\"modelica://Bicycle.Interfaces.RealInput\">RealInput</a>): <code>phi</code>
(rad), <code>phi_dot</code> (rad/s); outputs (<a
href=\"modelica://Bicycle.Interfaces.RealOutput\">RealOutput</a>): <code>T</code> (steer torque,
N.m), <code>theta</code> (upper-body lean, rad). The FMU has the same input and output names.
Modelica twin of the Python block <code>LeanSteer</code>
(<code>cosim.cosimulation.controllers</code>).</p>
</html>"));
end LeanSteer;
