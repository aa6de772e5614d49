within Bicycle.Mechanics.Joints;
model ActuatedRevolute "Revolute joint driven by a torque input, with an optional linear spring and damper"
  extends Bicycle.Mechanics.Joints.PartialActuatedRevolute;
  parameter Real c(final quantity = "RotationalSpringConstant", final unit = "N.m/rad", min = 0) = 0 "Stiffness of the spring (torque per angle; neutral at zero angle)";
  parameter Real d(final quantity = "RotationalDampingConstant", final unit = "N.m.s/rad", min = 0) = 0 "Damping (torque per rate)";
equation
  tau = tau_in - c*angle - d*omega;
  Ej = 0.5*c*angle^2;
  Fa = tau - frame_b.F[k];
  annotation(
    Icon(graphics = {
      Line(origin = {0, 30}, points = {{43.3, 25}, {35.4, 35.4}, {25, 43.3}, {12.9, 48.3}, {0, 50}, {-12.9, 48.3}, {-25, 43.3}, {-35.4, 35.4}, {-43.3, 25}}, color = {0, 0, 0}, arrow = {Arrow.None, Arrow.Filled}, arrowSize = 8, smooth = Smooth.Bezier)}),
    Documentation(info = "<html><p>A revolute joint (<a
href=\"modelica://Bicycle.Mechanics.Joints.PartialRevolute\">PartialRevolute</a>) with the torque
<code>tau_in</code> between frame_a and frame_b and a spring (stiffness <code>c</code>, neutral at
zero angle) and damper (<code>d</code>) in parallel: <code>tau = tau_in - c*angle - d*omega</code>;
the spring's energy <code>c*angle^2/2</code> counts in the system's energy.</p></html>"));
end ActuatedRevolute;
