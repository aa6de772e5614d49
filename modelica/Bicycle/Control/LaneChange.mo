within Bicycle.Control;
block LaneChange "Lane change by counter-steering: lateral error -> heading -> roll demand -> steer torque"
  extends Bicycle.Icons.Block;
  parameter Bicycle.Units.Position y_ref = 1 "Lateral offset of the new lane (positive to the right)";
  parameter Bicycle.Units.Time t_start = 1 "Time of the lane-change command";
  parameter Real k_y(unit = "rad/m") = 0.1 "Heading demand per metre of lateral error";
  parameter Real k_psi(unit = "1") = 1 "Roll demand per radian of heading error";
  parameter Real kp(unit = "N.m/rad") = 20 "Steer torque per radian of roll error";
  parameter Real kd(unit = "N.m.s/rad") = 10 "Steer torque per rad/s of roll rate";
  Bicycle.Interfaces.RealInput phi(final quantity = "Angle", final unit = "rad", displayUnit = "deg") "Roll angle (positive leaning right)"
    annotation(Placement(transformation(extent = {{-140, 40}, {-100, 80}})));
  Bicycle.Interfaces.RealInput phi_dot(final quantity = "AngularVelocity", final unit = "rad/s") "Roll rate"
    annotation(Placement(transformation(extent = {{-140, 0}, {-100, 40}})));
  Bicycle.Interfaces.RealInput psi(final quantity = "Angle", final unit = "rad", displayUnit = "deg") "Heading (positive turning right)"
    annotation(Placement(transformation(extent = {{-140, -40}, {-100, 0}})));
  Bicycle.Interfaces.RealInput y(final quantity = "Length", final unit = "m") "Lateral position (positive to the right)"
    annotation(Placement(transformation(extent = {{-140, -80}, {-100, -40}})));
  Bicycle.Interfaces.RealOutput T(final quantity = "Torque", final unit = "N.m") "Steer torque (positive steering right)"
    annotation(Placement(transformation(extent = {{100, -10}, {120, 10}})));
protected
  Bicycle.Units.Position y_cmd "Commanded lateral position";
  Bicycle.Units.Angle phi_ref "Roll demand";
equation
  // Stateless: sampled at communication points, so the step of y_cmd needs no event.
  y_cmd = if time >= t_start - 1e-12 then y_ref else 0;
  phi_ref = k_psi*(k_y*(y_cmd - y) - psi);
  T = kp*(phi - phi_ref) + kd*phi_dot;
  annotation(
    Icon(graphics = {
      Line(points = {{-90, -40}, {90, -40}}, color = {128, 128, 128}, pattern = LinePattern.Dash),
      Line(points = {{-90, 40}, {90, 40}}, color = {128, 128, 128}, pattern = LinePattern.Dash),
      Line(points = {{-90, 0}, {90, 0}}, color = {192, 192, 192}),
      Line(points = {{-90, -20}, {-20, -20}, {20, 20}, {90, 20}}, color = {0, 0, 127}, thickness = 1, smooth = Smooth.Bezier),
      Text(extent = {{-150, -150}, {150, -110}}, textString = "y_ref=%y_ref", textColor = {0, 0, 0})}),
    __Cosim(export = true),
    Documentation(info = "<html>
<p>Inputs (<a href=\"modelica://Bicycle.Interfaces.RealInput\">RealInput</a>): <code>phi</code>
(rad), <code>phi_dot</code> (rad/s), <code>psi</code> (rad), <code>y</code> (m); output (<a
href=\"modelica://Bicycle.Interfaces.RealOutput\">RealOutput</a>): <code>T</code> (steer torque,
N.m). The FMU has the same input and output names. Modelica twin of the Python block
<code>LaneChange</code> (<code>cosim.cosimulation.controllers</code>).</p>
<p>Meijaard conventions (y, psi, phi positive to the right), for
<code>Bicycles.WhippleLinear</code>.</p>
</html>"));
end LaneChange;
