within Bicycle.Bicycles;
model WhippleRiderTwist "Nonlinear Whipple bicycle with a rider whose upper body leans and twists: two hip hinges, each with stiffness, damping and a torque input"
  extends Bicycle.Bicycles.WhippleRider(n = 8, redeclare Bicycle.Mechanics.Rider.LeanTwistHinge hip(c = kU, d = cU, cT = kT, dT = cT, twist0 = twist0, twistRate0 = u_twist0));
  parameter Real kT(final quantity = "RotationalSpringConstant", final unit = "N.m/rad", min = 0) = kU "Passive stiffness of the twist hinge (twist torque per twist angle)";
  parameter Real cT(final quantity = "RotationalDampingConstant", final unit = "N.m.s/rad", min = 0) = cU "Passive damping of the twist hinge (twist torque per twist rate)";
  parameter Bicycle.Units.Angle twist0 = 0 "Initial twist angle of the upper body";
  parameter Bicycle.Units.AngularVelocity u_twist0 = 0 "Initial twist rate of the upper body";
  Bicycle.Interfaces.RealInput T_twist(final quantity = "Torque", final unit = "N.m") "Twist torque of the rider on the upper body about its vertical axis, positive turning the upper body right"
    annotation(Placement(transformation(extent = {{-220, 170}, {-200, 190}}), iconTransformation(extent = {{-140, -40}, {-100, 0}})));
  output Bicycle.Units.Angle twist = hip.twist.angle "Twist angle of the upper body about its vertical axis (coordinate 8), positive turning right";
  output Bicycle.Units.AngularVelocity u_twist = hip.twist.omega "Twist rate of the upper body (independent speed)";
equation
  connect(T_twist, hip.tau_twist) annotation(Line(points = {{-210, 180}, {-160, 180}, {-160, 158}, {-124, 158}}, color = {0, 0, 127}));
  annotation(
    experiment(StartTime = 0, StopTime = 10, Tolerance = 1e-10, Interval = 0.01),
    Documentation(info = "<html>
<p><a href=\"modelica://Bicycle.Bicycles.WhippleRider\">WhippleRider</a> with the hip of
<a href=\"modelica://Bicycle.Mechanics.Rider.LeanTwistHinge\">LeanTwistHinge</a>: the upper body
leans about the rear frame's longitudinal axis (<code>beta</code>, coordinate 7, as in
<code>WhippleRider</code>) and twists about its own vertical axis (<code>twist</code>, coordinate
8). Each hinge has a spring, a damper and the rider's torque (<code>T_beta</code>,
<code>T_twist</code>). The new joint owns its coordinate, so this model only raises the number of
generalized speeds <code>n</code> and names the new hinge; no other component changes.</p>
<p>With the twist hinge held (<code>kT</code> large, or the hinge locked) the model is
<code>WhippleRider</code>.</p>
</html>"));
end WhippleRiderTwist;
