within Bicycle.Components;
model LeaningUpperBody "Upper body of the rider, leaning relative to the rear frame by a prescribed angle, eq (22)"
  extends Bicycle.Icons.UpperBodyIcon;
  parameter Bicycle.Units.Mass m_r(min = 1e-6) = Bicycle.Records.Astrom2005SecondOrder.m_r "Mass m_r of the upper body";
  parameter Bicycle.Units.MomentOfInertia J_r(min = 1e-9) = Bicycle.Records.Astrom2005SecondOrder.J_r "Moment of inertia J_r of the upper body with respect to the x axis (coefficient of der(theta,2) in (22))";
  parameter Bicycle.Units.Length h_r(min = 0) = Bicycle.Records.Astrom2005SecondOrder.h_r "Distance h_r from the centre of mass of the upper body to its lean axis";
  parameter Bicycle.Units.Acceleration g(min = 1e-6) = Bicycle.Records.Astrom2005SecondOrder.g "Gravitational acceleration";
  input Bicycle.Units.Angle theta "Lean angle of the upper body relative to the frame, positive to the right (same sense as phi)";
  Bicycle.Interfaces.Roll roll "Roll axis of the frame that carries the upper body"
    annotation(Placement(transformation(extent = {{-110, -70}, {-90, -50}})));
  Bicycle.Interfaces.LeanOutput lean "Inertia-weighted lean J_r*theta for the momentum balance of the frame"
    annotation(Placement(transformation(origin = {80, -110}, extent = {{-10, -10}, {10, 10}}, rotation = -90)));
equation
  lean.H = J_r*theta;
  // The leaning upper body shifts its weight by h_r*theta: torque m_r*g*h_r*theta on the frame.
  roll.tau = -m_r*g*h_r*theta;
  annotation(
    Icon(graphics = {
      Line(points = {{75, 29.9}, {51.3, 41}, {26, 47.7}, {0, 50}, {-26, 47.7}, {-51.3, 41}, {-75, 29.9}}, color = {255, 0, 0}, thickness = 0.75, arrow = {Arrow.Filled, Arrow.Filled}, arrowSize = 6, smooth = Smooth.Bezier),
      Text(extent = {{40, 0}, {100, -50}}, textString = "θ", textColor = {0, 0, 0})}),
    Documentation(info = "<html>
<p>The terms of (22) that the lean angle <code>theta</code> adds to the frame: the gravity torque
<code>m_r*g*h_r*theta</code> through the roll axis and the inertial coupling
<code>J_r*der(theta,2)</code> through the lean connector, as <code>J_r*theta</code> (the frame is
written in momentum form, so the lean angle is never differentiated; see
<code>RearFrameWithLean</code>). The lean angle is an input: the rider's neuromuscular lean
dynamics are not modelled. Physically <code>J_r &lt; J</code> and <code>m_r &lt; m</code>.
<code>h_r = 0</code> (lean axis through the centre of mass of the upper body) is allowed.</p>
</html>"));
end LeaningUpperBody;
