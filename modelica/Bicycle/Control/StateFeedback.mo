within Bicycle.Control;
block StateFeedback "State feedback on steer torque (LQR autopilot): T = -(K1*phi + K2*delta + K3*phi_dot + K4*delta_dot)"
  extends Bicycle.Icons.Block;
  parameter Real K1(unit = "N.m/rad") = 0 "Gain on roll angle";
  parameter Real K2(unit = "N.m/rad") = 0 "Gain on steer angle";
  parameter Real K3(unit = "N.m.s/rad") = 0 "Gain on roll rate";
  parameter Real K4(unit = "N.m.s/rad") = 0 "Gain on steer rate";
  Bicycle.Interfaces.RealInput phi(final quantity = "Angle", final unit = "rad", displayUnit = "deg") "Roll angle"
    annotation(Placement(transformation(extent = {{-140, 40}, {-100, 80}})));
  Bicycle.Interfaces.RealInput delta(final quantity = "Angle", final unit = "rad", displayUnit = "deg") "Steer angle"
    annotation(Placement(transformation(extent = {{-140, 0}, {-100, 40}})));
  Bicycle.Interfaces.RealInput phi_dot(final quantity = "AngularVelocity", final unit = "rad/s") "Roll rate"
    annotation(Placement(transformation(extent = {{-140, -40}, {-100, 0}})));
  Bicycle.Interfaces.RealInput delta_dot(final quantity = "AngularVelocity", final unit = "rad/s") "Steer rate"
    annotation(Placement(transformation(extent = {{-140, -80}, {-100, -40}})));
  Bicycle.Interfaces.RealOutput T(final quantity = "Torque", final unit = "N.m") "Steer torque"
    annotation(Placement(transformation(extent = {{100, -10}, {120, 10}})));
equation
  T = -(K1*phi + K2*delta + K3*phi_dot + K4*delta_dot);
  annotation(
    Icon(graphics = {
      Text(extent = {{-70, 50}, {90, -10}}, textString = "T = -K x", textColor = {0, 0, 0}),
      Text(extent = {{-70, -20}, {90, -70}}, textString = "LQR", textColor = {128, 128, 128}),
      Text(extent = {{-96, 70}, {-60, 50}}, textString = "φ", textColor = {0, 0, 0}),
      Text(extent = {{-96, 30}, {-60, 10}}, textString = "δ", textColor = {0, 0, 0}),
      Text(extent = {{-96, -10}, {-60, -30}}, textString = "φ'", textColor = {0, 0, 0}),
      Text(extent = {{-96, -50}, {-60, -70}}, textString = "δ'", textColor = {0, 0, 0})}),
    __Cosim(export = true),
    Documentation(info = "<html>
<p>Inputs (<a href=\"modelica://Bicycle.Interfaces.RealInput\">RealInput</a>): <code>phi</code>,
<code>delta</code> (rad), <code>phi_dot</code>, <code>delta_dot</code> (rad/s); output (<a
href=\"modelica://Bicycle.Interfaces.RealOutput\">RealOutput</a>): <code>T</code> (steer torque,
N.m). The FMU has the same input and output names. Modelica twin of the Python block
<code>StateFeedback</code> (<code>cosim.cosimulation.controllers</code>).</p>
<p>The Python block <code>LQR</code> designs the gains and exports this block with them
(Examples.WhippleLinearLQRDelay).</p>
</html>"));
end StateFeedback;
