within Bicycle.Control;
block PID "PID rider: T = -kp*phi - ki*(integral of phi) - kd*phi_dot"
  extends Bicycle.Icons.Block;
  parameter Real kp(unit = "N.m/rad") = 10 "Gain from roll angle to steer torque";
  parameter Real ki(unit = "N.m/(rad.s)") = 1 "Gain from the integral of the roll angle to steer torque";
  parameter Real kd(unit = "N.m.s/rad") = 1 "Gain from roll rate to steer torque";
  Bicycle.Interfaces.RealInput phi(final quantity = "Angle", final unit = "rad", displayUnit = "deg") "Roll angle"
    annotation(Placement(transformation(extent = {{-140, 20}, {-100, 60}})));
  Bicycle.Interfaces.RealInput phi_dot(final quantity = "AngularVelocity", final unit = "rad/s") "Roll rate"
    annotation(Placement(transformation(extent = {{-140, -60}, {-100, -20}})));
  Bicycle.Interfaces.RealOutput T(final quantity = "Torque", final unit = "N.m") "Steer torque"
    annotation(Placement(transformation(extent = {{100, -10}, {120, 10}})));
  Real phi_int(unit = "rad.s", start = 0, fixed = true) "Integral of the roll angle";
equation
  der(phi_int) = phi;
  T = -kp*phi - ki*phi_int - kd*phi_dot;
  annotation(
    Icon(graphics = {
      Text(extent = {{-80, 50}, {80, -30}}, textString = "PID", textColor = {0, 0, 0}),
      Text(extent = {{-150, -150}, {150, -110}}, textString = "kp=%kp, ki=%ki, kd=%kd", textColor = {0, 0, 0})}),
    __Cosim(export = true),
    Documentation(info = "<html>
<p>Inputs (<a href=\"modelica://Bicycle.Interfaces.RealInput\">RealInput</a>): <code>phi</code>
(roll angle, rad), <code>phi_dot</code> (roll rate, rad/s); output (<a
href=\"modelica://Bicycle.Interfaces.RealOutput\">RealOutput</a>): <code>T</code> (steer torque,
N.m). The FMU has the same input and output names. Modelica twin of the Python block
<code>PID</code> (<code>cosim.cosimulation.controllers</code>).</p>
<p>The integral of the roll angle is the block's one state (0 at the start); the output depends on
both inputs without delay.</p>
</html>"));
end PID;
